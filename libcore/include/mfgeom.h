/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mfgeom.h - the whole public C API of libmfgeom: manufacturing geometry for CAD/CAM. */
#ifndef MFGEOM_H
#define MFGEOM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define MFG_API __declspec(dllexport)
#else
#define MFG_API __attribute__((visibility("default")))
#endif

/*
 * Conventions (every capability follows them):
 *  - Every fallible function returns an mfg_status.  On failure a human-readable
 *    detail is available from mfg_last_error() (thread-local, valid until the next
 *    mfg_ call on the same thread).  Output arguments are left untouched on failure,
 *    and nothing is half-written: either all outputs are produced or none.
 *  - The library never aborts, exits or prints, and has no global mutable state:
 *    any number of threads may call it at once on distinct or shared const objects.
 *  - Inputs are flat arrays of double / int64_t that map one-to-one onto numpy.
 *  - Results allocated by the library are released with the documented mfg_*_free
 *    function, never with the caller's free().
 *  - Coordinates and tolerances must be 0 or between MFG_MIN_COORD and MFG_MAX_COORD
 *    in magnitude (2^-200 .. 2^200); within that range the exact predicates can neither
 *    overflow nor underflow, so they are exact for every input accepted.  Other values
 *    (NaN, Inf, 1e-300, 1e300) are rejected with MFG_ERR_INVALID.
 */

#define MFG_VERSION_MAJOR 0
#define MFG_VERSION_MINOR 1
#define MFG_VERSION_PATCH 0

/* Accepted magnitudes of non-zero coordinates and tolerances (2^-200 and 2^200). */
#define MFG_MIN_COORD 6.2230152778611417e-61
#define MFG_MAX_COORD 1.6069380442589903e+60

typedef enum mfg_status {
    MFG_OK = 0,
    MFG_ERR_NULL = 1,         /* a required pointer argument was NULL */
    MFG_ERR_INVALID = 2,      /* NaN/Inf/out-of-range value, negative tolerance, bad count */
    MFG_ERR_DEGENERATE = 3,   /* input too small to define the object (e.g. ring < 3 vertices) */
    MFG_ERR_NOMEM = 4,        /* allocation failed */
    MFG_ERR_INTERNAL = 5,     /* a broken invariant: please report */
    MFG_ERR_CANCELLED = 6     /* the progress callback asked to stop (see mfg_progress) */
} mfg_status;

/* Static English name of a status code ("ok", "null argument", ...). Never NULL. */
MFG_API const char *mfg_status_str(mfg_status status);

/* Detail of the last failure on the calling thread ("" if none). Never NULL. */
MFG_API const char *mfg_last_error(void);

/* Library version as "MAJOR.MINOR.PATCH". */
MFG_API const char *mfg_version(void);

/*
 * Progress and cancel (one mechanism for every long entry point).
 *
 * Each long computation has a `_p` variant taking a last argument
 * `const mfg_progress *progress`; the plain function is that variant with progress NULL.
 * With progress NULL or progress->callback NULL nothing is reported and nothing changes.
 * Otherwise callback(user, fraction, stage) is called on the calling thread only (worker
 * threads of mfg_medial_surface_p never call it), synchronously:
 *   - once at the start of each stage (with the stage's first fraction), then
 *   - after every bounded amount of work inside the stage (a fixed number of work units
 *     chosen so that calls come every few milliseconds to a few tens of milliseconds of
 *     work on a 2020s desktop core; the units do not depend on time, so two runs on the
 *     same input with one thread make the same calls).  A few sequential steps are not
 *     split (a sort, the sweep's closed-mesh check, the merge of the medial sheets, the
 *     medial axis' output): their interval grows with the result, about 0.1-0.2 s for a
 *     sweep of 1 s (test_progress_cancel interval prints the largest gap), and
 *   - once at the end with fraction 1 and stage "<family>: done".
 * fraction is in [0, 1] and never decreases within one call; it is an estimate (stages
 * are weighted by their typical share of the time).  stage is a static string from the
 * lists below (compare it with strcmp; it stays valid for the life of the library).
 * A nonzero return from the callback stops the computation: the entry point then frees
 * everything it allocated, writes nothing to its outputs and returns MFG_ERR_CANCELLED,
 * and mfg_last_error() says "<function>: cancelled in stage "<stage>"" (the stage of
 * the call that returned nonzero).  The callback must not call back into the library on
 * the same thread before it returns (its error detail would be overwritten); it may be
 * shared between threads only if it is itself thread-safe.  No state is kept between
 * calls: the library stays reentrant.
 *
 * Stages, in order, per entry point:
 *   mfg_rotational_sweep_p  "sweep: setup", "sweep: contour", "sweep: strips",
 *                           "sweep: intersections", "sweep: faces", "sweep: boundary",
 *                           "sweep: output", "sweep: done" (contour .. boundary repeat,
 *                           with a fraction that still only grows, in the rare case that
 *                           the envelope is built again with other steps)
 *   mfg_medial_surface_p    "medial: elements", "medial: octree", "medial: sheets",
 *                           "medial: junctions", "medial: assembly", "medial: done"
 *   mfg_medial_axis_p       "axis: setup", "axis: branches", "axis: output", "axis: done"
 *   mfg_max_intersection_p, mfg_level_regions_p, mfg_min_intersection_p
 *                           "maxisect: sets", "maxisect: search", "maxisect: regions",
 *                           "maxisect: done"
 *   mfg_ray_blocked_p       "rays: index", "rays: queries", "rays: done"
 *   mfg_wall_thickness      the medial stages (to 0.9, without "medial: done"), then
 *                           "thickness: balls", "thickness: points", "thickness: done"
 */
typedef int (*mfg_progress_fn)(void *user, double fraction, const char *stage);

typedef struct mfg_progress {
    mfg_progress_fn callback; /* NULL: no reports, no cancel */
    void *user;               /* passed back unchanged */
} mfg_progress;

/* ------------------------------------------------------------------------- */
/* Tolerance-based point classification (Chung & Park, seed 002)             */
/* ------------------------------------------------------------------------- */

/* Classification codes (stored as uint8_t in the output arrays). */
typedef enum mfg_class {
    MFG_OUT = 0, /* outside the region, farther than tol from its boundary */
    MFG_IN = 1,  /* inside, farther than tol from the boundary */
    MFG_ON = 2   /* within tol of the boundary */
} mfg_class;

/*
 * A region is a set of rings given as one flat vertex array and ring offsets:
 *   xy[2*k], xy[2*k+1]       x and y of vertex k
 *   ring_offsets[0..nrings]  ring r uses vertices ring_offsets[r] .. ring_offsets[r+1]-1;
 *                            ring_offsets[0] must be 0 and the sequence non-decreasing.
 * Each ring is closed implicitly (last vertex to first); a repeated closing vertex is
 * harmless.  Rings may self-intersect, repeat vertices or contain collinear runs.
 * Inside is decided by the even-odd rule over all rings.
 *
 * A point T is ON when its Euclidean distance to the boundary (the union of all
 * closed edges) is <= tol, decided exactly (no rounding error) for all inputs in range;
 * otherwise IN or OUT by parity.  With tol = 0, ON means exactly on an edge.
 * The answer does not depend on ring start vertices or orientation.
 */

/* One-shot: classify npoints points pts[2*i], pts[2*i+1] into out[i] (MFG_OUT/IN/ON).
 * Uses the outcode method of the paper; O(n) per point. */
MFG_API mfg_status mfg_classify_points(const double *xy, const int64_t *ring_offsets,
                                       int64_t nrings, const double *pts, int64_t npoints,
                                       double tol, uint8_t *out);

/* Prepared region: a grid index built once, then many queries.  Gives answers
 * identical to mfg_classify_points. Immutable after creation: safe to share between
 * threads. */
typedef struct mfg_region mfg_region;

MFG_API mfg_status mfg_region_new(const double *xy, const int64_t *ring_offsets,
                                  int64_t nrings, double tol, mfg_region **out_region);
MFG_API mfg_status mfg_region_classify(const mfg_region *region, const double *pts,
                                       int64_t npoints, uint8_t *out);
/* Shape of a prepared region's index (mfg_region_info).  The index is a uniform grid;
 * a cell holding edges has a quadtree whose leaves either list a few edges or are
 * "ordered" (edges sorted across a slab, searched by bisection). */
struct mfg_region_info {
    int64_t columns, rows;    /* the uniform grid */
    int64_t edge_cells;       /* grid cells within reach of an edge */
    int64_t grid_entries;     /* edge entries of those cells (before refinement) */
    int64_t edge_entries;     /* edge entries held by all leaves (list + ordered) */
    int64_t list_entries, ordered_entries;
    int64_t nodes;            /* quadtree nodes, leaves and inner */
    int64_t list_leaves, ordered_leaves;
    int64_t max_depth;        /* deepest leaf (0: a grid cell that was not split) */
    int64_t max_list;         /* longest list a query may scan */
    int64_t bytes;            /* memory held by the region, approximately */
};
/* Fills *out (a struct; the name is shared with this function, as with stat()). */
MFG_API mfg_status mfg_region_info(const mfg_region *region, struct mfg_region_info *out);
/* Older form: columns, rows, edge_cells, edge_entries of mfg_region_info. */
MFG_API mfg_status mfg_region_stats(const mfg_region *region, int64_t stats_out[4]);
/* Releases a region from mfg_region_new. NULL is allowed. */
MFG_API void mfg_region_free(mfg_region *region);


/* ------------------------------------------------------------------------- */
/* Visibility maps on the unit sphere (Ha 2001, seed 000)                    */
/* ------------------------------------------------------------------------- */

/* Kinds of a visibility map (or of any spherical set handled below); stored as int32_t
 * in mfg_spoly.kind, mfg_regions.kinds and the kinds[] inputs. */
typedef enum mfg_vm_kind {
    MFG_VM_NULL = 0,    /* empty: the normals lie in no closed hemisphere */
    MFG_VM_POINT = 1,   /* one direction, or two antipodal ones (see below) */
    MFG_VM_EDGE = 2,    /* an arc of one great circle (possibly the whole circle) */
    MFG_VM_POLYGON = 3, /* a spherical convex polygon with interior */
    MFG_VM_FACE = 4     /* output only (mfg_min_intersection): a face of the arrangement
                         * of the input sets, not convex in general; its shape is not
                         * computed (no vertices), only a direction inside it */
} mfg_vm_kind;

/* Largest angular distance (radians) of a point of a drafted map from the polygon
 * returned for it (mfg_visibility_map with draft_angle > 0; see there). */
#define MFG_DRAFT_TOL 1e-4

/*
 * A spherical convex set, as returned by mfg_visibility_map (owned by the library,
 * released with mfg_spoly_free).  vertices holds nvertices unit vectors (x, y, z).
 *  POLYGON: nvertices >= 3, counter-clockwise seen from outside the sphere (the
 *           interior is on the left of each edge v[i] -> v[i+1]); every edge is the
 *           minor great arc between consecutive vertices (always shorter than pi).
 *           A hemisphere has 3 vertices on its great circle; a lune has 4 (its two
 *           corners and the midpoints of its two half circles).
 *  EDGE:    nvertices >= 3 along one great circle: the arc from v[0] through v[1] ...
 *           to v[n-1]; consecutive vertices are less than pi apart (so an arc of
 *           length pi, whose ends are antipodal, is stored with its midpoint and is
 *           never ambiguous).  closed = 1 marks a whole great circle, stored as 3
 *           vertices 120 degrees apart.
 *  POINT:   nvertices = 1, or 2 antipodal directions when every normal lies on one
 *           great circle in no half of it (both poles of that circle qualify).
 *  NULL:    nvertices = 0.
 */
typedef struct mfg_spoly {
    int32_t kind;
    int32_t closed;
    int64_t nvertices;
    double *vertices;
} mfg_spoly;

/*
 * Visibility map VM(P) = { d : d . p >= 0 for all p in P } of m normals (3*m doubles,
 * any non-zero length: only directions matter; duplicates allowed).  Kinds and hull
 * turns are decided by exact predicates on the given doubles; output vertices are
 * rounded unit vectors.  The negative map -VM(P) is VM(-P).
 * draft_angle (radians, 0 <= a < pi/2) shrinks the map to { d : d . p^ >= sin a }; that
 * set is bounded by small circles, so the result is a polygon inscribed in it with
 * great arcs: every direction returned satisfies the draft, and no point of the true set
 * is farther than MFG_DRAFT_TOL (1e-4 rad) from the polygon.
 */
MFG_API mfg_status mfg_visibility_map(const double *normals, int64_t m, double draft_angle,
                                      mfg_spoly **out_map);
/* Releases a result of mfg_visibility_map (or any mfg_spoly from this library). */
MFG_API void mfg_spoly_free(mfg_spoly *poly);

/* ------------------------------------------------------------------------- */
/* Maximum intersection of spherical convex polygons (Ha 2001, seed 000 s.4) */
/* ------------------------------------------------------------------------- */

/*
 * Input: npolys (1 .. 2^40) spherical convex sets in the mfg_spoly layout, flattened:
 *   vertices[3*k ..]           all vertices, polygon after polygon: unit vectors (length
 *                              1 within 1e-6; anything else is refused as a mix-up)
 *   offsets[0..npolys]         polygon i uses vertices offsets[i] .. offsets[i+1]-1;
 *                              offsets[0] = 0, non-decreasing, at most 2^40; at most
 *                              2^31 - 1 vertices per set
 *   kinds[i]                   MFG_VM_NULL .. MFG_VM_POLYGON (NULL sets are ignored)
 *   closed[i]                  0 or 1; 1 only for an EDGE that is a whole great circle
 *                              (the array may be NULL: all 0)
 *   weights[i]                 finite, >= 0 (NULL: all 1); 0 ignores the set.  Only the
 *                              ratios matter: the result is the same for all weights
 *                              scaled by any factor (up to rounding of the factor).
 *                              Weights and sums closer than 2^-44 (n + 1) W count as
 *                              equal (W: the total weight of the n sets taking part,
 *                              i.e. not NULL and not of weight 0; ignored sets enter
 *                              nothing): a set far lighter than that is a tie, it
 *                              decides no maximum but still covers.
 * Each set must have the shape its kind says, within 1e-9 rad, or the call fails with
 * MFG_ERR_INVALID and a message naming the set: a POINT's two vertices antipodal; an
 * EDGE's vertices on one great circle, each piece shorter than pi and turning the same
 * way, less than a whole turn (closed: exactly one); a POLYGON convex and
 * counter-clockwise (every turn to the left, once round its interior).
 * Sets are closed.  Coverage is decided with an angular tolerance of MFG_SPHERE_TOL:
 * boundaries closer than that count as touching, so two maps sharing a boundary circle
 * (common for faces with a common normal) overlap along it.
 *
 * Output (mfg_regions, released with mfg_regions_free):
 *   weight          the maximum covered weight (levels: exactly the level asked for)
 *   nregions        number of regions; for region r:
 *   kinds[r]        MFG_VM_POLYGON, MFG_VM_EDGE or MFG_VM_POINT (MFG_VM_FACE: minimum)
 *   closed[r]       1 for an EDGE region that is a whole great circle (as in mfg_spoly)
 *   vertex_offsets, vertices   its vertices as in mfg_spoly (polygons counter-clockwise)
 *   cover_offsets, cover       indices of the input sets that cover it
 *   centres[3r..]   a representative direction: the centre of the largest circle inscribed
 *                   in the region (the smallest enclosing circle of the poles of its edges,
 *                   as in the paper); an arc's midpoint; the point itself
 *   margins[r]      that circle's angular radius: how far the direction may move and stay
 *                   in the region (0 for arcs and points)
 * Regions are sorted by decreasing margin (ties: by centre coordinates), so region 0 is
 * the recommended one; the result does not depend on the order of the input sets.
 */
#define MFG_SPHERE_TOL 1e-10

typedef struct mfg_regions {
    double weight;
    int64_t nregions;
    int32_t *kinds;
    int32_t *closed;
    int64_t *vertex_offsets;
    double *vertices;
    int64_t *cover_offsets;
    int64_t *cover;
    double *centres;
    double *margins;
} mfg_regions;

/* All regions of maximum covered weight. */
MFG_API mfg_status mfg_max_intersection(const double *vertices, const int64_t *offsets,
                                        const int32_t *kinds, const int32_t *closed,
                                        int64_t npolys, const double *weights,
                                        mfg_regions **out);

/* Level k: every region whose cover set is locally maximal (adding any other set would
 * leave the region) and whose weight is >= level.  With level = the maximum this is
 * mfg_max_intersection; lower levels also return the runner-up local maxima. */
MFG_API mfg_status mfg_level_regions(const double *vertices, const int64_t *offsets,
                                     const int32_t *kinds, const int32_t *closed,
                                     int64_t npolys, const double *weights, double level,
                                     mfg_regions **out);

/* Minimum intersection: the least covered weight over the sphere and, per region of
 * that coverage (a face of the arrangement, not convex in general), its cover set and a
 * representative direction inside it.  Such a region has kind MFG_VM_FACE, no vertices
 * (its shape is not computed) and margin 0. */
MFG_API mfg_status mfg_min_intersection(const double *vertices, const int64_t *offsets,
                                        const int32_t *kinds, const int32_t *closed,
                                        int64_t npolys, const double *weights,
                                        mfg_regions **out);

/* The three functions above with progress and cancel (mfg_progress; NULL: none). */
MFG_API mfg_status mfg_max_intersection_p(const double *vertices, const int64_t *offsets,
                                          const int32_t *kinds, const int32_t *closed,
                                          int64_t npolys, const double *weights,
                                          mfg_regions **out, const mfg_progress *progress);
MFG_API mfg_status mfg_level_regions_p(const double *vertices, const int64_t *offsets,
                                       const int32_t *kinds, const int32_t *closed,
                                       int64_t npolys, const double *weights, double level,
                                       mfg_regions **out, const mfg_progress *progress);
MFG_API mfg_status mfg_min_intersection_p(const double *vertices, const int64_t *offsets,
                                          const int32_t *kinds, const int32_t *closed,
                                          int64_t npolys, const double *weights,
                                          mfg_regions **out, const mfg_progress *progress);

/* Releases a result of the three functions above. NULL is allowed. */
MFG_API void mfg_regions_free(mfg_regions *regions);

/* ------------------------------------------------------------------------- */
/* Closed triangle meshes (input of the rotational sweep and the medial surface) */
/* ------------------------------------------------------------------------- */

/*
 * A triangle mesh is given as
 *   xyz[3*k ..]        x, y, z of vertex k (0 <= k < nvertices)
 *   triangles[3*t ..]  the vertex indices of triangle t, counter-clockwise seen from
 *                      outside (right-hand rule: the normal points out of the solid)
 * Counts are 0 .. 2^40; a coordinate outside the accepted range (NaN, Inf, 1e300) or an
 * index outside 0 .. nvertices-1 is rejected with MFG_ERR_INVALID naming it.
 *
 * The rotational sweep and the medial surface take a closed solid: a closed, consistently
 * oriented 2-manifold triangle mesh.  mfg_mesh_check measures how far a mesh is from
 * that; mfg_mesh_check_closed refuses what is not one, saying what is wrong first.
 * The terms (an edge is an unordered pair of vertex indices used by a triangle side):
 *   boundary edge        used by one triangle side only (the mesh has a hole there)
 *   non-manifold edge    used by more than two triangle sides
 *   inconsistent edge    used by two triangles that run along it the same way (one of
 *                        them is flipped)
 *   non-manifold vertex  its triangles form more than one fan, counting as joined two
 *                        triangles that share an edge at the vertex used by exactly two
 *                        sides (two solids touching at a corner; the ends of a
 *                        non-manifold edge count too)
 *   degenerate triangle  zero area, decided exactly (the three coordinate projections of
 *                        the triangle are all collinear), or a vertex index repeated;
 *                        a triangle with a repeated index has no sides (it counts
 *                        only here: not in the edges, components, volume or area)
 *   component            a set of triangles connected through shared edges
 * volume: the signed volume enclosed, the sum of the signed tetrahedra of the triangles
 * with a common apex (outward triangles: positive).  Its sign is trusted only beyond
 * an error bound of 2^-47 times the sum of the absolute values of the products of the
 * determinants (a few units of rounding each); within it the volume counts as zero.
 * area: the sum of the triangle areas.  bbox: min x, min y, min z, max x, max y, max z
 * of the vertices used by triangles (all zero when there is none).
 * Every count is independent of the order of the triangles and of the vertex a triangle
 * starts with (the volume and area only up to rounding).  Time O(n log n), memory O(n).
 */
typedef struct mfg_mesh_report {
    int64_t nvertices, ntriangles;
    int64_t boundary_edges;
    int64_t nonmanifold_edges;
    int64_t inconsistent_edges;
    int64_t nonmanifold_vertices;
    int64_t degenerate_triangles;
    int64_t unused_vertices;   /* vertices no triangle uses (harmless) */
    int64_t components;
    double volume;
    double area;
    double bbox[6];
} mfg_mesh_report;

/* Fills *out for any mesh with valid counts, coordinates and indices (MFG_OK even when
 * the mesh is open, non-manifold or flipped): the report says what it is. */
MFG_API mfg_status mfg_mesh_check(const double *xyz, int64_t nvertices,
                                  const int64_t *triangles, int64_t ntriangles,
                                  mfg_mesh_report *out);

/* Like mfg_mesh_check, but succeeds (and fills *out) only for a closed solid: at least
 * one triangle, no repeated index in a triangle, not every triangle of zero area, no
 * boundary, non-manifold or inconsistent edge, no non-manifold vertex, and a positive
 * volume.  Otherwise MFG_ERR_INVALID (MFG_ERR_DEGENERATE for no triangles, zero-area
 * triangles only and zero volume) with a detail naming the first problem in that order
 * and how many there are, e.g. "mesh is not closed: 12 boundary edges (first: vertices
 * 3-7)" or "negative volume -1: the triangles face inward".  Zero-area triangles
 * among others, unused vertices and several components are accepted (a solid with
 * a cavity has an inward inner shell: only the total volume must be positive) as long
 * as the shells bound a solid: two triangles sharing no vertex must not cross (decided
 * exactly: an edge through the other's interior, or coplanar interiors overlapping;
 * shells that only touch pass) -- "shells cross: triangles 3 and 16 intersect" -- and
 * a shell facing out must lie outside every other shell, a cavity inside exactly one
 * ("nested shells: ...", by winding numbers; not checked beyond 4096 shells), and no
 * shell may enclose zero volume ("flat shell: ...": faces folded onto each other).  Unite
 * overlapping parts before.  Cost: O(n log n) (a bounding-volume tree; about 2 s for
 * 10^6 triangles). */
MFG_API mfg_status mfg_mesh_check_closed(const double *xyz, int64_t nvertices,
                                         const int64_t *triangles, int64_t ntriangles,
                                         mfg_mesh_report *out);

/* An indexed triangle mesh returned by the library (released with mfg_mesh_free). */
typedef struct mfg_mesh {
    int64_t nvertices;
    int64_t ntriangles;
    double *vertices;    /* 3 * nvertices */
    int64_t *triangles;  /* 3 * ntriangles */
} mfg_mesh;

/* Welds a triangle soup (as read from STL): xyz_soup holds 9 doubles per triangle (its
 * three corners).  Corners with exactly the same coordinates (the same doubles; -0 and
 * +0 are the same) become one vertex; nothing else is merged.  Vertices are numbered in
 * the order of their first appearance in the soup and the triangles keep their order
 * and corner order, so a soup cut from an indexed mesh welds back to it.  A triangle
 * whose corners coincide keeps its repeated index (mfg_mesh_check counts it degenerate). */
MFG_API mfg_status mfg_mesh_weld(const double *xyz_soup, int64_t ntriangles,
                                 mfg_mesh **out_mesh);
/* Releases a result of mfg_mesh_weld. NULL is allowed. */
MFG_API void mfg_mesh_free(mfg_mesh *mesh);

/* ------------------------------------------------------------------------------------ */
/* Demouldability by rays (issue 17): does a ray along +d / -d leave the part?            */
/* ------------------------------------------------------------------------------------ */
/*
 * For each point p_i (points[3*i ..]) the two open rays p + s*d (s > 0, the core side)
 * and p - s*d (s > 0, the cavity side) are tested against the triangles of a mesh (as
 * for mfg_mesh_check: any mesh with valid coordinates and indices, closed or not), and
 * blocked_out[i] gets the bits
 *   MFG_RAY_BLOCKED_POS  the ray along +d crosses the interior of a triangle
 *   MFG_RAY_BLOCKED_NEG  the ray along -d crosses the interior of a triangle
 *   MFG_RAY_GRAZES_POS   the ray along +d passes exactly through an edge or a vertex of a
 *                        triangle (without its interior): it touches, it is not counted
 *                        as blocked (through the shared edge of two faces of a closed
 *                        mesh it may or may not enter the solid; the caller samples
 *                        other points)
 *   MFG_RAY_GRAZES_NEG   likewise along -d
 * decided exactly (orientation predicates on the doubles given; no tolerance), with:
 *   - a triangle whose plane is parallel to d (or contains the ray: a wall parallel to d
 *     along which the ray slides) and a zero-area triangle never block nor graze;
 *   - a crossing at s = 0 (p itself lies on the triangle) does not count;
 *   - own_triangle[i] (0 .. ntriangles-1, or -1 for none) is the triangle p_i was sampled
 *     on: it is ignored (a rounded sample point may lie a hair off its plane).
 *     own_triangle may be NULL: no triangle is ignored.
 * direction must be non-zero (its length does not matter).  Time O(n log n + m (log n +
 * k)) where k is the number of triangles whose projected bounding box (along d) holds a
 * point's projection (a 2-D bounding-volume hierarchy; a few for tessellations),
 * memory O(n + m).
 * Errors: MFG_ERR_NULL, MFG_ERR_INVALID (counts, a coordinate or the direction NaN, Inf,
 * out of range or zero, an index out of range), MFG_ERR_NOMEM; blocked_out is not
 * written on failure.
 */
#define MFG_RAY_BLOCKED_POS 1
#define MFG_RAY_BLOCKED_NEG 2
#define MFG_RAY_GRAZES_POS 4
#define MFG_RAY_GRAZES_NEG 8

MFG_API mfg_status mfg_ray_blocked(const double *xyz, int64_t nvertices,
                                   const int64_t *triangles, int64_t ntriangles,
                                   const double *points, const int64_t *own_triangle,
                                   int64_t npoints, const double direction[3],
                                   uint8_t *blocked_out);
/* mfg_ray_blocked with progress and cancel (mfg_progress; NULL: none). */
MFG_API mfg_status mfg_ray_blocked_p(const double *xyz, int64_t nvertices,
                                     const int64_t *triangles, int64_t ntriangles,
                                     const double *points, const int64_t *own_triangle,
                                     int64_t npoints, const double direction[3],
                                     uint8_t *blocked_out, const mfg_progress *progress);

/* ------------------------------------------------------------------------------------ */
/* Rotational swept volume (seed 003)                                                    */
/* ------------------------------------------------------------------------------------ */
/*
 * The volume SV = union over t in [0, angle] of R(t)*O swept by the closed solid O (a
 * closed, consistently outward oriented 2-manifold triangle mesh, as accepted by
 * mfg_mesh_check_closed) rotated about the axis through axis_point along axis_direction
 * (right-handed: counter-clockwise seen from the tip of axis_direction) by angles 0 .. angle.
 *
 *   angle      radians, 0 < angle <= 2*pi (values within 1e-12 of 2*pi mean a full turn:
 *              the solid of revolution)
 *   tolerance  absolute, in model units, > 0: the result contains SV and its boundary
 *              lies within tolerance of the boundary of SV, up to the rounding of its
 *              points (to the output grid below; where the rounding passes weld points a
 *              few grid cells apart, by at most 2^-30 of the power of two of E, far below
 *              the smallest tolerance accepted; docs/design/sweep.md).
 *              Refused (MFG_ERR_INVALID, the message names the smallest accepted value)
 *              below max(2^12 ulps of the largest |coordinate| of the mesh and axis point,
 *              2^-24 of E), E = the largest |coordinate - axis point|: what the
 *              coordinates cannot resolve, or work without bound.  Above E / 16 it is
 *              computed to about E / 16 (a tighter result meets the request).
 * A part whose own extent (the largest side of its bounding box) is below 2^-36 of E is
 * refused (MFG_ERR_INVALID): the computation cannot resolve it (choose an axis point
 * nearer the part); so is one below 2^(14 - 49) of the largest |coordinate| (the result
 * is rounded to about 2^-49 of it: move the part nearer the origin).
 *
 * The computation runs at unit scale (everything divided by the power of two of E) on a
 * canonically numbered copy of the mesh, so the input scaled by 2^k gives the result
 * scaled by 2^k bit for bit, and any reordering of the triangles, their start corners or
 * the vertex numbers gives the same result arrays.
 *
 * On MFG_OK, *out_mesh is a closed, outward oriented triangle mesh of SV without
 * self-intersections (released with mfg_mesh_free), its points on the grid of 2^-50 of
 * the power of two of its largest coordinate (a planar face of the input comes out on its
 * plane to that grid: z = 0.6 may come out as 0.59999999999999964), and, when out_stats is not NULL, *out_stats holds its volume, area and
 * bounding box.  Errors: MFG_ERR_NULL, MFG_ERR_INVALID (NaN/Inf, axis direction of zero
 * length, angle or tolerance out of range, an open / non-manifold / inconsistently
 * oriented mesh: the detail says what and how many, as mfg_mesh_check_closed does),
 * MFG_ERR_DEGENERATE (no triangles, zero volume), MFG_ERR_NOMEM.  Nothing is written on
 * failure.
 */
typedef struct mfg_sweep_stats {
    double volume;   /* enclosed by the result mesh */
    double area;     /* of the result mesh */
    double bbox[6];  /* xmin, ymin, zmin, xmax, ymax, zmax of the result mesh */
} mfg_sweep_stats;

MFG_API mfg_status mfg_rotational_sweep(const double *xyz, int64_t nvertices,
                                        const int64_t *triangles, int64_t ntriangles,
                                        const double axis_point[3],
                                        const double axis_direction[3], double angle,
                                        double tolerance, mfg_mesh **out_mesh,
                                        mfg_sweep_stats *out_stats);
/* mfg_rotational_sweep with progress and cancel (mfg_progress; NULL: none). */
MFG_API mfg_status mfg_rotational_sweep_p(const double *xyz, int64_t nvertices,
                                          const int64_t *triangles, int64_t ntriangles,
                                          const double axis_point[3],
                                          const double axis_direction[3], double angle,
                                          double tolerance, mfg_mesh **out_mesh,
                                          mfg_sweep_stats *out_stats,
                                          const mfg_progress *progress);

/* ------------------------------------------------------------------------- */
/* Medial axis of a planar face (issue 9, section 2)                         */
/* ------------------------------------------------------------------------- */

/*
 * The medial axis of a face (the locus of centres of maximal inscribed discs), as
 * branches -- polylines with the clearance radius (distance to the boundary) at every
 * sample, parabolic arcs sampled -- joined at junctions.  Flat arrays, as mfg_regions.
 *
 *   branch_offsets[0..nbranches]  branch b is samples branch_offsets[b] ..
 *                                 branch_offsets[b+1]-1 (npoints in all)
 *   points[2*i], points[2*i+1]    sample i;  radii[i] its distance to the boundary
 *   branch_ends[2*b], [2*b+1]     junction index at the branch's first / last sample,
 *                                 -1 for a leaf (a convex corner of the face, radius 0)
 *   junction_points[2*j], [2*j+1], junction_radii[j]
 *   junction_degree[j]            number of branches leaving junction j
 *   junction_offsets[0..njunctions] into junction_elements: the boundary elements the
 *                                 junction's disc touches: edge e (from vertex e to the
 *                                 next vertex of its ring, indices of the caller's xy)
 *                                 -> e; a reflex vertex k -> -1-k.
 * A junction's disc touches >= 3 elements (the centre of a square touches 4 and has
 * degree 4); points where the axis passes from one element to another without a third
 * (the ends of a parabolic arc) are samples, not junctions.  Junctions joined by a
 * branch shorter than tol are one junction when the group so joined spans less than tol
 * (elements: the union; degree: the branches that end at it; the other branches' ends
 * moved onto it, by < tol); a longer chain of short branches (around an annulus at a
 * tolerance above the junctions' spacing) stays as it is.
 * Canonical order: junctions by (x, y, r); junction elements ascending; a branch runs
 * from its lower-numbered junction to the other end (a leaf end always last); branches
 * sorted by (start junction, end junction with leaves after all junctions, end point,
 * middle sample).  So the result does not depend on the rings' start vertices,
 * orientation or order, up to rounding (two junctions whose x differ by rounding only
 * may swap).
 */
struct mfg_medial_axis {
    int64_t nbranches;
    int64_t *branch_offsets;
    int64_t npoints;
    double *points;
    double *radii;
    int64_t *branch_ends;
    int64_t njunctions;
    double *junction_points;
    double *junction_radii;
    int64_t *junction_degree;
    int64_t *junction_offsets;
    int64_t *junction_elements;
};

/* Rings exactly as mfg_classify_points (flat xy + ring_offsets; outer boundary and holes,
 * the interior by the even-odd rule; any orientation).  A run of consecutive vertices
 * within 1e-11 of the input's extent of its first (equal ones, a closing vertex that
 * repeats the first up to rounding) is one vertex, the run's last; vertices where the
 * boundary goes straight on are dropped.  tol > 0 in model units: samples lie within tol of the true axis and linearly
 * interpolated radii between samples within tol of the true clearance.
 * Errors (nothing is allocated, *out is left untouched): MFG_ERR_NULL; MFG_ERR_INVALID
 * for NaN/Inf or out-of-range coordinates, tol <= 0, bad offsets, rings that cross or
 * touch each other or themselves (the detail names the two edges: the axis of such a
 * boundary is not defined); MFG_ERR_DEGENERATE for a ring with fewer than 3 distinct
 * vertices or no area; MFG_ERR_NOMEM.  Release the result with mfg_medial_axis_free.
 * Cost: O(n log n) typical (a BVH of the edges; each event is an exact root found by a
 * branch and bound; a branch from a junction searches only the boundary beyond the arc
 * between its two elements, so a junction touching all n edges of a circle's polygon
 * costs O(n log n) in all).  Present limits: element ids in junction_elements refer to the caller's
 * vertices, so they change with the ring start vertex (positions do not); a third element
 * grazing the disc (a double root) is not an event. */
MFG_API mfg_status mfg_medial_axis(const double *xy, const int64_t *ring_offsets,
                                   int64_t nrings, double tol,
                                   struct mfg_medial_axis **out);
/* mfg_medial_axis with progress and cancel (mfg_progress; NULL: none). */
MFG_API mfg_status mfg_medial_axis_p(const double *xy, const int64_t *ring_offsets,
                                     int64_t nrings, double tol,
                                     struct mfg_medial_axis **out,
                                     const mfg_progress *progress);
/* Releases a result of mfg_medial_axis.  NULL is allowed. */
MFG_API void mfg_medial_axis_free(struct mfg_medial_axis *axis);

/* ------------------------------------------------------------------------- */
/* Medial surface of a polyhedral solid (issue 9, section 1; seed 004)        */
/* ------------------------------------------------------------------------- */

/* Kinds of boundary elements of the merged polyhedron.  Element ids: faces 0 .. nfaces-1,
 * then edges, then vertices; each group sorted by a key of its coordinates, so no id
 * depends on the order of the input triangles. */
typedef enum { MFG_ELEM_VERTEX = 0, MFG_ELEM_EDGE = 1, MFG_ELEM_FACE = 2 } mfg_element_kind;

/* Seam and junction kinds (the paper's section 3.2):
 *   BRANCH      three (seam) / four (junction) or more sheets meet;
 *   SMOOTH      a sheet passes from one element pair to another (e.g. (face, face) to
 *               (face, reflex edge)) without a third sheet;
 *   DEGENERATE  a curve where >= 4 elements are equidistant (the axis of a square prism). */
typedef enum { MFG_MEDIAL_BRANCH = 0, MFG_MEDIAL_SMOOTH = 1, MFG_MEDIAL_DEGENERATE = 2 } mfg_medial_kind;

/* Bisector forms of two elements (1 .. 11): 1 plane-plane parallel, 2 plane-plane,
 * 3 plane-line parallel, 4 plane-line perpendicular, 5 plane-line oblique, 6 plane-point,
 * 7 line-line parallel, 8 line-line crossing, 9 line-line skew, 10 line-point,
 * 11 point-point. */

/* Flag: the full medial surface (default: the major part, sheets between elements whose
 * closures are disjoint). */
#define MFG_MEDIAL_FULL 1u

/*
 * The medial surface (locus of centres of maximal inscribed balls) with every piece tied
 * to the boundary elements it touches and the radius (distance to the boundary) at every
 * point.  Flat, offset-prefixed arrays as mfg_regions.
 *
 * Elements of the merged polyhedron:
 *   element_kinds[e]           mfg_element_kind
 *   element_convex[e]          edges: 1 convex, 0 reflex; faces and vertices: -1
 *   face_of_triangle[t]        the face of input triangle t (-1: zero area)
 *   face_planes[4f..]          outward unit normal n and offset d (n.x = d)
 *   edge_segments[6i..]        edge i (element nfaces + i): its two end points
 *   vertex_points[3j..]        vertex j (element nfaces + nedges + j)
 * Sheets (surface pieces equidistant from 2 elements), triangle meshes:
 *   sheet_elements[2s..]       the two elements, ascending;  sheet_forms[s] 1 .. 11
 *   sheet_vertex_offsets[s .. s+1]    into sheet_vertices (3 per vertex), sheet_radii
 *   sheet_triangle_offsets[s .. s+1]  into sheet_triangles (3 per triangle; indices local
 *                                     to the sheet's vertices)
 * Seams (curves where >= 3 elements are equidistant), polylines joining junctions:
 *   seam_kinds[c]; seam_point_offsets[c .. c+1] into seam_points (3 per), seam_radii;
 *   seam_element_offsets[c .. c+1] into seam_elements (ascending);
 *   seam_ends[2c..]            junction index at the first / last point, or -1
 * Junctions (centres of maximal balls touching >= 4 elements):
 *   junction_kinds[j]; junction_points[3j..]; junction_radii[j];
 *   junction_element_offsets[j .. j+1] into junction_elements (ascending)
 * Cost, for benchmarks: cells_visited (octree cells tested), leaves, leaf_size.
 */
typedef struct mfg_medial {
    int64_t nelements, nfaces, nedges, nvertices, ntriangles;
    int32_t *element_kinds;
    int32_t *element_convex;
    int64_t *face_of_triangle;
    double *face_planes;
    double *edge_segments;
    double *vertex_points;

    int64_t nsheets;
    int64_t *sheet_elements;
    int32_t *sheet_forms;
    int64_t *sheet_vertex_offsets;
    int64_t *sheet_triangle_offsets;
    double *sheet_vertices;
    double *sheet_radii;
    int64_t *sheet_triangles;

    int64_t nseams;
    int32_t *seam_kinds;
    int64_t *seam_point_offsets;
    double *seam_points;
    double *seam_radii;
    int64_t *seam_element_offsets;
    int64_t *seam_elements;
    int64_t *seam_ends;

    int64_t njunctions;
    int32_t *junction_kinds;
    double *junction_points;
    double *junction_radii;
    int64_t *junction_element_offsets;
    int64_t *junction_elements;

    int64_t cells_visited, leaves;
    double leaf_size;
} mfg_medial;

/* The medial surface of the solid bounded by a closed, consistently oriented triangle
 * mesh (2-manifold, watertight, planar faces: adjacent coplanar triangles are merged into
 * one face).  A curved solid comes in tessellated; the result is then the medial surface
 * of that polyhedron.  tolerance > 0 (absolute, model units): sheet vertices lie on the
 * analytic bisector up to rounding, sheets within tolerance of the true bisector, seam
 * polylines within tolerance of the true seams.  flags: 0 (major part) or
 * MFG_MEDIAL_FULL.  nthreads: 0 = the online CPUs; the result does not depend on it, nor
 * on the order of the triangles.
 * Errors (nothing is allocated, *out left untouched): MFG_ERR_NULL; MFG_ERR_INVALID (NaN,
 * out-of-range coordinates or indices, open, non-manifold or inconsistently oriented
 * mesh, tolerance not finite and > 0 or not below the bounding-box diagonal, unknown
 * flags); MFG_ERR_DEGENERATE (no triangles, zero-area triangles only, zero volume);
 * MFG_ERR_NOMEM.  Release the result with mfg_medial_free. */
MFG_API mfg_status mfg_medial_surface(const double *xyz, int64_t nvertices,
                                      const int64_t *triangles, int64_t ntriangles,
                                      double tolerance, uint32_t flags, int32_t nthreads,
                                      mfg_medial **out);
/* mfg_medial_surface with progress and cancel (mfg_progress; NULL: none).  Only the
 * calling thread calls the callback; the worker threads stop at their next unit. */
MFG_API mfg_status mfg_medial_surface_p(const double *xyz, int64_t nvertices,
                                        const int64_t *triangles, int64_t ntriangles,
                                        double tolerance, uint32_t flags, int32_t nthreads,
                                        mfg_medial **out, const mfg_progress *progress);
/* Releases a result of mfg_medial_surface.  NULL is allowed. */
MFG_API void mfg_medial_free(mfg_medial *medial);

/* ------------------------------------------------------------------------- */
/* Wall thickness from the medial surface (issue 21, section 4)               */
/* ------------------------------------------------------------------------- */

/* Default of min_angle below: 2 pi / 3 (120 degrees). */
#define MFG_WALL_ANGLE 2.0943951023931957

/*
 * Local wall thickness at points on the boundary of the solid of a medial result: the
 * diameter of the maximal inscribed ball that touches the point.  The balls are those of
 * the medial surface (its sheets, seams and junctions: each touches its elements at their
 * foot points, the closest points of the elements to its centre); a ball counts as a
 * wall's when two of the points it touches are at least min_angle apart seen from its
 * centre: the two sides of a wall face each other (180 degrees, less the taper of a
 * wedge), the two faces at a convex right-angled corner are 90 degrees apart -- a corner
 * is not a thin wall, else every box would be thin at its edges.  Each point takes the
 * smallest of the wall balls that touch it; a point that none touches (near a convex
 * edge, on a narrow face between two walls) takes the ball touching the nearest touched
 * point.  Radii are interpolated linearly over the foot triangles of a sheet's triangles
 * (exact on plane-plane sheets), along the foot segments of seams.
 *
 *   points[3i..]       the query points (any points; meant on the boundary)
 *   thickness[i]       out: 2 r of the point's ball
 *   centres[3i..]      out (NULL: not wanted): the ball's centre
 *   gaps[i]            out (NULL: not wanted): distance from the point to the point its
 *                      ball touches (0 up to rounding where a ball touches the point)
 * min_angle in (0, pi] (radians; MFG_WALL_ANGLE is the default the workbench uses).
 * Errors (outputs untouched): MFG_ERR_NULL; MFG_ERR_INVALID (npoints < 0 or too large,
 * a point or min_angle not finite or out of range); MFG_ERR_DEGENERATE (no ball of the
 * medial surface counts as a wall's: e.g. an empty medial result); MFG_ERR_NOMEM. */
MFG_API mfg_status mfg_medial_thickness(const mfg_medial *medial, const double *points,
                                        int64_t npoints, double min_angle, double *thickness,
                                        double *centres, double *gaps);

/* mfg_medial_surface_p (flags as there) followed by mfg_medial_thickness, the medial
 * result freed before return.  Progress stages: those of mfg_medial_surface_p (mapped to
 * the first 90 %), then "thickness: balls", "thickness: points", "thickness: done".  Errors
 * as the two functions' (the detail names mfg_wall_thickness). */
MFG_API mfg_status mfg_wall_thickness(const double *xyz, int64_t nvertices,
                                      const int64_t *triangles, int64_t ntriangles,
                                      double tolerance, uint32_t flags, int32_t nthreads,
                                      const double *points, int64_t npoints, double min_angle,
                                      double *thickness, double *centres, double *gaps,
                                      const mfg_progress *progress);

#ifdef __cplusplus
}
#endif

#endif /* MFGEOM_H */
