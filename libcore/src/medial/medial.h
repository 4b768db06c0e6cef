/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial.h - private: the 3-D medial surface (issue 9; Lee & Lee, the medial surface of a
 * polyhedron; the design is docs/design/medial.md, cited below as "design N").  The
 * boundary elements of the merged polyhedron (faces, edges, vertices), their distances
 * restricted to their Voronoi regions (the paper's special bisectors), and the roots of
 * the bisector of two elements (design 1 and 4.0): elements.c, bisector.c; then one
 * section per stage: the BVH (bvh.c), the octree (octree.c), the sheet extraction
 * (sheets.c), the sheet simplification (simplify.c) and the junction search (junctions.c).
 * The assembly into mfg_medial has its own header, medial/assembly.h. */
#ifndef MFG_MEDIAL_H
#define MFG_MEDIAL_H

#include <math.h>
#include <stdint.h>

#include "mfgeom.h"
#include "common/mfg_internal.h"

#include "common/vec3.h"

/* Rounding allowance of the medial computations, relative to its base (mostly L, the
 * bounding-box diagonal): distances of a computed point that agree within 1e-9 L count as
 * equal (a sheet vertex on its pair's bisector, a trimmed point still in its regions),
 * far above the rounding of distances up to L and far below any tolerance (>= L / 2^20). */
#define MD_ROUND_REL 1e-9
/* Sheet triangles smaller than this times h^2 are dropped (design 4.1): slivers of the
 * marching tets, far below the h^2 / 2 of a triangle that matters. */
#define MD_AREA_DROP 1e-6

/* Element kinds, as the public mfg_element_kind will number them. */
enum { MD_VERTEX = 0, MD_EDGE = 1, MD_FACE = 2 };

/*
 * The elements of a closed mesh: the solid's faces (adjacent coplanar triangles merged),
 * edges (chains of mesh edges between two faces, straight to within eta) and vertices
 * (the chains' ends).  Element ids: faces 0 .. nfaces-1, then edges, then vertices; each
 * group is sorted by a key of its coordinates, so no id depends on the triangle order.
 * Everything below is owned by the struct (md_elements_free).
 */
typedef struct md_elements {
    int64_t nfaces, nedges, nverts, nelements;
    double diag; /* L: the bounding-box diagonal */
    double eta;  /* near-coplanar merge threshold: min(1e-3 tol, max(1e-7 L, 2^-20 max|x|)) */

    /* The mesh, with each triangle's corners rotated so that the lexicographically smallest
     * one comes first (orientation kept): tris[3t + k], t in input order. */
    int64_t nv, nt;
    double *xyz;
    int64_t *tris;

    /* Faces, by face index f (= element id). */
    double *face_plane;         /* 4 per face: outward unit normal n, offset delta (n.x = delta) */
    int32_t *face_axis;         /* dominant coordinate of n: the plane is projected along it */
    int64_t *face_tri_offsets;  /* nfaces + 1 */
    int64_t *face_tris;         /* the face's non-degenerate triangles, ascending */
    int64_t *face_side_offsets; /* nfaces + 1 */
    int64_t *face_sides;        /* the sides 3t + k of its triangles on its boundary */
    /* A box tree over the sides of each face with more than MD_SIDE_TREE_MIN of them
     * (element_distances.c): nodes side_tree_offsets[f] .. [f + 1] (none: a short face),
     * leaves holding positions q of face_sides, listed in side_tree_perm. */
    int64_t *side_tree_offsets; /* nfaces + 1 */
    struct md_side_node *side_nodes;
    int64_t *side_tree_perm;    /* face_side_offsets[nfaces] */

    /* Edges, by edge index i (element id nfaces + i). */
    double *edge_seg;           /* 6 per edge: A then B, A the lexicographically smaller end */
    double *edge_dir;           /* 3 per edge: unit u = (B - A) / len */
    double *edge_len;           /* 1 per edge */
    int64_t *edge_faces;        /* 2 per edge: the face ids, ascending */
    double *edge_w;             /* 6 per edge: each face's in-plane unit normal at the edge,
                                   pointing into the face (same order as edge_faces) */
    int64_t *edge_ends;         /* 2 per edge: vertex element ids of A and B */
    int32_t *edge_convex;       /* 1 convex (the solid's angle < 180 deg), 0 reflex */

    /* Vertices, by vertex index j (element id nfaces + nedges + j). */
    double *vert_xyz;           /* 3 per vertex */
    int64_t *vert_mesh;         /* its mesh vertex */
    int32_t *vert_region_empty; /* 1 when a face corner at it is >= 180 deg (design 1.7) */

    /* Closure: bound[bound_offsets[e] .. bound_offsets[e+1]) are the element ids in e's
     * relative boundary, ascending (a face: its edges and vertices; an edge: its ends). */
    int64_t *bound_offsets, *bound;
    /* Edge element ids at each vertex (vertex index j), ascending. */
    int64_t *vert_edge_offsets, *vert_edges;

    /* Tables in input order: the face of each triangle (-1 for zero area), and the
     * element whose relative interior holds each triangle side (from corner k to k+1 of
     * the rotated triangle) and corner (a face when it lies inside one). */
    int64_t *face_of_triangle, *side_elem, *corner_elem;
} md_elements;

/* ---- elements.c: the boundary elements ----------------------------------------------- */

/* Builds the elements of a closed mesh.  Refuses (with mfg_fail's detail) everything
 * mfg_mesh_require_closed refuses, and a tolerance that is not finite and > 0, >= L, or
 * below L / 2^20.  On failure *out is left zeroed (nothing to free). */
mfg_status md_elements_build(const double *xyz, int64_t nvertices, const int64_t *triangles,
                             int64_t ntriangles, double tolerance, md_elements *out);

/* Releases what md_elements_build allocated (a zeroed struct is fine). */
void md_elements_free(md_elements *el);

/* MD_FACE, MD_EDGE or MD_VERTEX for element id e. */
static inline int md_kind(const md_elements *el, int64_t e)
{
    return e < el->nfaces ? MD_FACE : (e < el->nfaces + el->nedges ? MD_EDGE : MD_VERTEX);
}

/* Carrier distance d_e^car: s_F = delta - n.x (signed, > 0 inside), the distance to the
 * edge's line, or to the vertex.  grad (may be NULL) gets its gradient: -n, the unit
 * vector from the foot on the line, or from the vertex (0 on the carrier itself). */
double md_dist_car(const md_elements *el, int64_t e, const double x[3], double grad[3]);

/* Margin of x in e's Voronoi region (design 1.7): >= 0 iff the foot of x on e's carrier
 * lies in e's closure (for a face also s_F >= 0); the value is the smallest of the
 * linear constraints l(x) (a face: the signed in-plane distance to its nearest boundary
 * side).  *which (may be NULL) gets the element of e's boundary whose constraint is the
 * smallest (a face's edge or an edge's end), or -1 (a face's s_F, a vertex's region). */
double md_region_margin(const md_elements *el, int64_t e, const double x[3], int64_t *which);

/* The faces' side trees (md_elements.side_nodes), once the faces' sides are known; 0 when
 * out of memory.  Why: md_region_margin is O(sides) per call without them, and a
 * tessellated round face has hundreds (the 625-segment cup's bottom, the ribbed tray's
 * floor with 212): 18-20 % of the whole medial surface's time. */
int md_side_trees_build(md_elements *el);

/* Restricted distance d_e: d_e^car when x is in e's Voronoi region, otherwise +INFINITY. */
double md_dist(const md_elements *el, int64_t e, const double x[3]);

/* Distance from x to e's closure (the face polygon, the segment, the point): 1-Lipschitz,
 * <= md_dist wherever that is finite; the octree's pruning bound (design 3). */
double md_dist_closed(const md_elements *el, int64_t e, const double x[3]);

/* 1 when one element lies in the other's closure (or a == b). */
int md_incident(const md_elements *el, int64_t a, int64_t b);

/* 1 when the closures of a and b meet (they share an edge or a vertex, or are incident). */
int md_adjacent(const md_elements *el, int64_t a, int64_t b);

/* D(x) = min_e d_e(x) over all elements (brute force; the BVH is bvh.c) and
 * the touching set {e : d_e(x) <= D + delta}, ascending, written to out (room for
 * nelements).  Returns its size; *D gets D(x) (+INFINITY when no region holds x). */
int64_t md_nearest_set_brute(const md_elements *el, const double x[3], double delta,
                             int64_t *out, double *D);

/* ---- bisector.c: bisector roots ------------------------------------------------------ */

/* The bisector forms of design 4.0, numbered as the public mfg_bisector_form will be. */
enum {
    MD_FORM_PLANE_PLANE_PARALLEL = 1, MD_FORM_PLANE_PLANE = 2,
    MD_FORM_PLANE_LINE_PARALLEL = 3, MD_FORM_PLANE_LINE_PERPENDICULAR = 4,
    MD_FORM_PLANE_LINE_OBLIQUE = 5, MD_FORM_PLANE_POINT = 6,
    MD_FORM_LINE_LINE_PARALLEL = 7, MD_FORM_LINE_LINE_CROSSING = 8, MD_FORM_LINE_LINE_SKEW = 9,
    MD_FORM_LINE_POINT = 10, MD_FORM_POINT_POINT = 11
};

/* The form (1 .. 11) of the bisector of elements a and b (either order), decided exactly
 * on the stored doubles: mfg_parallel3 and mfg_dot3_sign on the unit normals and
 * directions, mfg_orient3d on the edges' end points (crossing vs skew lines). */
int md_form(const md_elements *el, int64_t a, int64_t b);

/* g(s) = d_a^car(p + s (q - p)) - d_b^car(p + s (q - p)) for s in [0, 1].  When g(0) and
 * g(1) differ in sign (or one is 0), finds a root: one Newton step with the exact
 * gradients, then Illinois regula falsi safeguarded by bisection, stopping at
 * |g| <= 4u (d_a + d_b) or a 2-ulp bracket (design 4.0).  The result depends only on
 * (p, q) as given: callers pass the segment from its smaller key so that both
 * neighbours get the same bits.  Returns 1 with the point in out and s in *s_out (may be
 * NULL), or 0 (out untouched) when g does not change sign on the segment. */
int md_root_on_segment(const md_elements *el, int64_t a, int64_t b, const double p[3],
                       const double q[3], double out[3], double *s_out);

/* ---- bvh.c: the BVH, the distance field ---------------------------------------------- */

/* Closest points (Ericson 5.1.2 and 5.1.5), shared by the BVH and the wall thickness.
 * md_closest_on_seg: q on segment ab, returns 0 (a), 1 (b) or 2 (between); *t (may be
 * NULL) its parameter.  md_closest_on_tri: q on triangle abc, returns the feature (0..2
 * corners, 3..5 sides, 6 interior); w (may be NULL) q's barycentric weights of a, b, c. */
int md_closest_on_seg(const double *p, const double *a, const double *b, double *q, double *t);
int md_closest_on_tri(const double *p, const double *a, const double *b, const double *c,
                      double *q, double *w);

/* A bounding-volume hierarchy over the non-degenerate triangles of el (design 2): median
 * splits on centroid Morton codes (deterministic), leaves of <= 4 triangles, double
 * AABBs.  Immutable after md_bvh_build: queries from many threads at once are safe. */
typedef struct md_bvh md_bvh;

/* MFG_OK or MFG_ERR_NOMEM (*out NULL). */
mfg_status md_bvh_build(const md_elements *el, md_bvh **out);
void md_bvh_free(md_bvh *bvh);

/* Unsigned distance from x to the boundary; *elem (may be NULL) gets the element whose
 * relative interior holds the nearest boundary point (ties: the smallest id), *inside
 * (may be NULL) 1 when x is inside the solid (by the angle-weighted pseudonormal of that
 * element), 0 outside.  For x inside, this equals D(x) = min_e md_dist(e, x). */
double md_bvh_nearest(const md_bvh *bvh, const md_elements *el, const double x[3],
                      int64_t *elem, int *inside);

/* The elements whose closure meets the closed ball B(x, R) (faces, edges and vertices),
 * ascending, without duplicates.  Writes at most cap ids to out and returns the full
 * count (call again with more room when it is larger than cap). */
int64_t md_bvh_within(const md_bvh *bvh, const md_elements *el, const double x[3], double R,
                      int64_t *out, int64_t cap);

/* ---- octree.c: the adaptive octree --------------------------------------------------- */

/* The leaf lattice: leaf (i, j, k) is the cube [origin + h (i, j, k), origin + h (i+1, j+1,
 * k+1)].  Lattice point (i, j, k) is computed as origin[d] + h * (double)i_d, nothing else,
 * so that every leaf sharing the point gets the same bits. */
typedef struct md_lattice {
    double origin[3];
    double h;      /* leaf side: the largest S / 2^depth <= tolerance */
    int32_t depth; /* leaves per axis: 2^depth */
} md_lattice;

/* A leaf that a bisector may cross (design 3).  C: the candidate elements (every element
 * that can be nearest somewhere in the cell), ascending; P: the pairs (a < b, element ids)
 * whose bisector may cross the cell and be medial there (non-incident; in major mode
 * disjoint closures); nT: |T_2rho(centre)|, the elements within D + 2 rho at the centre
 * (>= 4: a junction or degenerate-seam leaf, design 4.3). */
typedef struct md_leaf {
    int32_t ijk[3];
    int32_t nC, nP, nT;
    int32_t level; /* 0: a leaf of side h; m > 0: a coarse plane leaf (design 3.4) of side
                      2^m h whose smallest lattice point is ijk, with C = P = one face pair */
    int64_t C_off; /* into md_leaves.C */
    int64_t P_off; /* into md_leaves.P (2 ids per pair) */
} md_leaf;

typedef struct md_leaves {
    md_lattice lat;
    int64_t nleaves;
    md_leaf *leaf;      /* sorted by (i, j, k) lexicographically: independent of threads */
    int64_t *C;         /* pooled candidate sets */
    int64_t *P;         /* pooled pairs */
    int64_t cells_visited;
} md_leaves;

/* Builds the leaves of the adaptive octree over el's bounding box: cells pruned when
 * outside the solid or when no pair of candidates can have a medial bisector in them;
 * candidates inherited from the parent below depth 3.  full: 0 major pairs only, 1 all
 * non-incident pairs.  nthreads >= 1.  Every leaf has side h (level 0): the uniform
 * lattice, whose soundness the tests check leaf by leaf.  MFG_OK, MFG_ERR_NOMEM (out
 * zeroed). */
mfg_status md_octree_build(const md_elements *el, const md_bvh *bvh, double tolerance,
                           int full, int nthreads, md_leaves *out);
/* The same with progress (mfg_prog, NULL: none; the caller has entered the stage) and,
 * when coarse is 1, the coarse plane leaves of design 3.4: a cell whose only candidates
 * are two faces, each holding the whole cell's projection, stops there (level > 0). */
mfg_status md_octree_build_p(const md_elements *el, const md_bvh *bvh, double tolerance,
                             int full, int coarse, int nthreads, md_leaves *out,
                             mfg_prog *prog);
void md_leaves_free(md_leaves *leaves);

/* ---- sheets.c: the sheet extraction on the analytic bisectors ------------------------ */

/* The sheets of all leaves' pairs before assembly (design 4.1): marching tetrahedra (6 Kuhn
 * tets per leaf) on f_ab = d_a^car - d_b^car, vertices by md_root_on_segment from the
 * segment's smaller lattice key, trimmed where another element is nearer or a or b leaves
 * its Voronoi region, with exact boundary points there.  Vertices are welded (one vertex
 * per (pair, lattice edge) or per boundary point).
 *   tri_pair[2t..]   the pair of triangle t (a < b)
 *   seg_*            seam segments: the trimmed boundary of the sheets, each with the
 *                    three elements equidistant there (ascending) and its kind
 *                    (MFG_MEDIAL_BRANCH when the third element is not incident to a or b,
 *                    MFG_MEDIAL_SMOOTH when it is a sub-element of a or b that left its
 *                    region). */
typedef struct md_soup {
    int64_t nverts;
    double *xyz;      /* 3 per vertex */
    double *radius;   /* D at the vertex */
    int64_t ntris;
    int64_t *tris;    /* 3 per triangle */
    int64_t *tri_pair;
    int64_t nsegs;
    int64_t *seg_verts;  /* 2 per segment, into xyz */
    int64_t *seg_elems;  /* 3 per segment */
    int32_t *seg_kind;
    int64_t *seg_pair;   /* 2 per segment: the pair (a < b) of the sheet it bounds (the
                            elements alone do not tell which of the 3 sheets) */
} md_soup;

mfg_status md_sheets_extract(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                             double tolerance, int nthreads, md_soup *out);
/* The same with progress (mfg_prog, NULL: none; the caller has entered the stage). */
mfg_status md_sheets_extract_p(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                               double tolerance, int nthreads, md_soup *out, mfg_prog *prog);
void md_soup_free(md_soup *soup);

/* ---- simplify.c: a sheet made coarse within the tolerance ---------------------------- */

/* Seam labels of the soup's vertices, for md_sheet_simplify: per soup vertex (label has
 * room for sp->nverts) -1 when no seam segment ends there (inside its sheet), the element
 * other than the segment's pair (seg_elems minus seg_pair) when every seam segment ending
 * there has the same one, -2 when they differ (a corner of the sheet: where its seam
 * meets another, at a junction).  Needs no memory. */
void md_soup_seam_labels(const md_soup *sp, int64_t *label);

/* One sheet of pair (a, b) (a connected piece of the soup's triangles of that pair, or
 * several: each piece is handled on its own), made coarse in place.  On entry sheet holds
 * nverts vertices and ntris triangles (consistently oriented, as md_sheets_extract makes
 * them); label (may be
 * NULL) per vertex its seam label (md_soup_seam_labels).  On return the same arrays hold
 * the kept vertices (those of the kept triangles), in their input order, unmoved, radii
 * unchanged, and the new triangles (never more of either); vmap (may be NULL) gets per
 * input vertex its new index or -1.
 *   planar bisectors (md_form 1, 2, 7, 11): each region triangulated again on its boundary
 *     loops only (mfg_merge_planar_groups), then boundary vertices removed as below;
 *   every sheet: half-edge collapses v -> u (u an existing neighbour), shortest edges first,
 *     accepted only when the new triangles stay within tolerance / 2 of the bisector
 *     (|d_a^car - d_b^car| / |grad| at their centroid, edge midpoints and 3 inner points),
 *     face the bisector's normal within 60 deg (no fold) and keep the mesh a manifold.  A
 *     boundary vertex goes only along the boundary, only when it and every boundary
 *     vertex removed between the new boundary edge's ends carry one seam label (-1, no
 *     seam segment there, goes with any; -2 never goes; label NULL: no labels) and stay
 *     within tolerance / 4 of it: the sheet's corners and boundary pinches stay, its
 *     edges follow the seams.
 * The result depends only on the input arrays (sorted orders, no threads).  MFG_OK, or
 * MFG_ERR_NOMEM with the arrays untouched. */
typedef struct md_sheet_mesh {
    int64_t nverts; /* vertices: xyz 3 each, radius 1 each */
    double *xyz;
    double *radius;
    int64_t ntris; /* triangles: tris 3 each, indices into the vertices */
    int64_t *tris;
} md_sheet_mesh;
mfg_status md_sheet_simplify(const md_elements *el, int64_t a, int64_t b, double tolerance,
                             const int64_t *label, md_sheet_mesh *sheet, int64_t *vmap);

/* ---- junctions.c: the junction search, junctions and degenerate seams ---------------- */

/* A point equidistant from a set of elements (design 4.3).  rank 3: an isolated point
 * (a junction); rank 2: a point of a curve of such points (a degenerate seam) whose
 * direction is dir. */
#define MD_JMAX 32
typedef struct md_junction {
    double x[3];
    double r;
    double dir[3];       /* rank 2: unit tangent of the degenerate seam; else 0 */
    int32_t rank;        /* 3 junction, 2 degenerate seam point */
    int32_t kind;        /* mfg_medial_kind */
    int32_t n;
    int64_t elems[MD_JMAX]; /* the touching elements, ascending */
} md_junction;

/* Where a junction is looked for: the box [lo, lo + side]^3 of the elements el (bvh may be
 * NULL: every element is a candidate), and the tolerance. */
typedef struct md_jbox {
    const md_elements *el;
    const md_bvh *bvh;
    const double *lo;
    double side, tolerance;
} md_jbox;

/* The paper's search for the points in the box equidistant from all of T (nT >= 4
 * element ids, ascending): subdivision down to side <= tolerance / 8, then Gauss-Newton
 * polish (md_junction_polish).  Writes at most cap results, returns their count (or -1
 * with mfg_fail on NOMEM). */
int md_junction_search(const md_jbox *B, const int64_t *T, int nT, md_junction *out, int cap);

/* Gauss-Newton on d_t0 = d_ti (i >= 1) from x0, with the SVD of the Jacobian (an incident
 * pair uses its region boundary instead); returns 1 with *out filled (rank, kind, the
 * elements within 1e-9 L of D) when it converges inside the box grown by tolerance. */
int md_junction_polish(const md_jbox *B, const double x0[3], const int64_t *T, int nT,
                       md_junction *out);

/* The point of the seam of S (nS >= 3 elements, ascending, equidistant along a curve)
 * nearest x0, and the seam's unit tangent there (either sign).  Returns 1 when
 * Gauss-Newton converges (residuals within 1e-9 L) at a point where the equations have
 * rank 2, else 0. */
int md_seam_point(const md_elements *el, const int64_t *S, int nS, const double x0[3],
                  double x[3], double dir[3]);

/* The elements touching the largest ball centred at x inside the solid (radius D(x)):
 * carrier distance within 1e-9 L of D and x in their Voronoi region up to 1e-9 L.  D is
 * taken from the elements (not the BVH's triangles), so it does not depend on the
 * triangle order.  bvh may be NULL (brute force).  Writes at most cap ids, ascending;
 * returns the full count (-1 on NOMEM); *D (may be NULL) gets D(x). */
int md_touching_set(const md_elements *el, const md_bvh *bvh, const double x[3], int64_t *out,
                    int cap, double *D);

/* The assembly (junction_search.c, sheet_assembly.c, seam_assembly.c, junction_recovery.c)
 * and the entry point (medial.c): medial/assembly.h. */

#endif
