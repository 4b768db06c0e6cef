/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/sweep.h - internal header of the sweep family: the rotational swept volume of a
 * closed polyhedron (seed 003, Baek & Shin).  The context (sw_ctx) and the types and
 * functions shared between the family's files:
 *
 *   setup.c      the solid in the axis frame, curves, bins
 *   gaps.c       gap-closing curves (case 1.3)
 *   circles.c    directed circles: the SV arcs of one circle
 *   cells.c      the meridian decomposition: grid, curve crossings, cut cells
 *   hidden.c     the meridian decomposition: triangles hidden in a cell
 *   quadtree.c   the meridian decomposition: cell analysis and the quadtree
 *   polygons.c   polygons of the decomposition
 *   lift.c       output vertices, lifts onto the front and back triangles
 *   walls.c      walls along the decomposition's edges
 *   wallmesh.c   walls tessellated, face pieces
 *   pinches.c    pinched edges paired
 *   shells.c     shells, slivers, twins, merged faces; the walls stage
 *   rotsweep.c   the entry point
 *
 * The paper's characterisation, made into a construction that cannot leave a crack:
 *
 *  - Directed circles.  Every point x lies on a circle about the axis, named by its
 *    meridian coordinates (r, z) (distance from the axis, height along it).  On that
 *    circle the solid O is a union of arcs [entry, exit]; because all points of the
 *    circle turn together, SV meets the circle in the union of the arcs
 *    [entry at t = 0, exit at t = theta] (the directed-circle rule).  circle_arcs()
 *    computes this exactly for one circle: the plane z = const cuts every triangle in a
 *    segment; the circle meets the segments at the roots of quadratics; a depth count
 *    along the circle gives O's arcs; extending each by theta and merging gives SV's.
 *    Each SV arc starts on a front face at t = 0 and ends on a back face turned by theta.
 *
 *  - The meridian decomposition.  The half-plane of (r, z) (the paper's H_ref, onto which
 *    RotProj projects the faces) is cut into cells by a quadtree.  A cell is accepted when
 *    the arc structure is the same all over it: which triangle starts and which ends every
 *    SV arc.  It changes only across the images of the mesh edges and of the silhouette
 *    lines inside faces (curves), at images of vertices, and where a front face at t = 0
 *    meets a back face at t = theta (the paper's case 1.3: the image of the 3-D segment
 *    B n R(theta) A, kept as a gap-closing curve).  A cell crossed by one curve is
 *    split along the chord between the curve's two crossings with the cell's sides; a
 *    cell holding one vertex image and only the curves that end there is split into a
 *    star round it (also round the junction of gap-closing curves; round an image on the
 *    axis, which lies on the side r = 0 of its cell, a half star); a cell crossed by
 *    several curves that do not cross in it is cut along all their chords.  Other cells
 *    are refined, down to a size below the tolerance; a cell
 *    still mixed there is cut into a fan round its centre and each piece takes the
 *    structure at its own centroid (the only approximation of the arrangement, within
 *    the smallest cell size).
 *
 *  - Lifting.  Every polygon of the decomposition carries its arc structure.  Over it, the
 *    start of an arc is a piece of one front triangle (the circle through each polygon
 *    corner meets the triangle's plane at one of two known roots), the end a piece of a
 *    back triangle turned by theta: flat polygons in the input's planes, exact up to
 *    rounding.  Corners on a curve use the curve's own 3-D point, so the pieces on both
 *    sides of an edge share their vertices.
 *
 *  - Walls.  Along every edge of the decomposition the arcs on its two sides are compared;
 *    where exactly one side covers an angle, the swept surface of revolution (plane,
 *    cone, cylinder or hyperboloid piece: the paper's silhouette faces, and the annular
 *    faces of faces perpendicular to the axis) closes the gap.  Walls are cut into strips
 *    at every angle where lines of the two sides cross, and tessellated on each circle at
 *    the angles of a per-radius grid (chord sag below half the tolerance) plus every arc
 *    end that any strip uses there, so neighbouring strips share their vertices.
 *
 * The result is the boundary of a union of "angular prisms" over the polygons: closed by
 * construction, each piece oriented by the side it bounds.
 */
#ifndef MFG_SWEEP_SWEEP_H
#define MFG_SWEEP_SWEEP_H

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/hashmap.h"
#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "mesh/planar_merge.h"

typedef struct sw_ctx sw_ctx;

static inline int64_t dbits(double x)
{
    int64_t b;
    if (x == 0)
        x = 0; /* -0 and +0 are one key */
    memcpy(&b, &x, sizeof b);
    return b;
}

/* Angle in [0, 2 pi). */
static inline double wrap_angle(double a)
{
    a = fmod(a, MFG_TWO_PI);
    if (a < 0)
        a += MFG_TWO_PI;
    if (a >= MFG_TWO_PI)
        a = 0;
    return a;
}

/* Signed difference a - b brought into (-pi, pi]. */
static inline double angle_diff(double a, double b)
{
    double d = fmod(a - b, MFG_TWO_PI);
    if (d > MFG_PI)
        d -= MFG_TWO_PI;
    else if (d <= -MFG_PI)
        d += MFG_TWO_PI;
    return d;
}

typedef struct sw_tri {
    int64_t v[3];
    double n[3];       /* outward normal (not unit) */
    double d;          /* plane: n . x = d */
    double phi0;       /* direction of the horizontal part of n: the roots of a circle
                          with the plane lie at phi0 +- delta */
    double zmin, zmax, rmin, rmax;
    int vertical_ok;   /* the horizontal part of n is not zero: a circle can cross it */
} sw_tri;

/* A curve of the meridian decomposition: the image of a mesh edge or of a silhouette
 * segment inside a face, both straight 3-D segments p0 -> p0 + dir. */
typedef struct sw_curve {
    double p0[3], dir[3];
    double qa, qb, qc;  /* r^2(u) = qa u^2 + qb u + qc */
    double zmin, zmax, rmin, rmax;
    int64_t tri[2];     /* triangles it bounds (tri[1] = -1 for a silhouette segment) */
    int64_t vtx[2];     /* mesh vertices at u = 0, 1 (-1 where not a vertex) */
    int64_t gexit;      /* a gap-closing curve (on the entry triangle tri[0]): the exit
                           triangle whose turn by theta meets it there, else -1 */
} sw_curve;

/* One end of an SV arc on a circle: a triangle and which of the circle's two roots with
 * its plane (sigma = +-1), the angle found at the sample (exit: before the turn). */
typedef struct sw_end {
    int64_t tri;
    int sigma;
    double phi;
} sw_end;

typedef struct sw_arc {
    sw_end start, end;
} sw_arc;

/* The SV arcs of a circle: full, or n arcs (stored in the context's arc pool). */
typedef struct sw_struct {
    int full;
    int64_t n, first;
    int64_t xfirst, xn;    /* the triangles the circle crosses (in c->xpool): a full
                              circle's structure does not name them */
} sw_struct;

#define SW_MAXCURVES 8
typedef struct sw_vtx2 {   /* a vertex of the meridian decomposition */
    double r, z;
    int64_t curve;         /* the curve it lies on (-1: none) */
    double u;              /* its parameter there */
    int64_t mvtx;          /* a mesh vertex whose image it is (-1: none) */
    int ncurves;           /* every curve through it (curves with one image merge here) */
    int64_t curves[SW_MAXCURVES];
    double us[SW_MAXCURVES];
} sw_vtx2;

typedef struct sw_poly {   /* a polygon of the decomposition */
    int64_t first, n;      /* its vertex ids in poly_verts, counter-clockwise in (r, z) */
    sw_struct st;
} sw_poly;

typedef struct sw_leaf {
    int64_t ix, iz;        /* lower-left corner, in finest units */
    int level;             /* size = 2^(lmax - level) finest units */
    int kind;              /* LEAF_* */
    int64_t cfirst, cn;    /* its curves in leaf_curves */
    int64_t split_curve;   /* LEAF_SPLIT: the curve along which it is cut */
    int nchords;           /* LEAF_CHORDS: its distinct chords */
    double cr, cz;         /* LEAF_STAR / LEAF_FAN: the centre */
    int64_t cvtx;          /* LEAF_STAR: a mesh vertex imaged at the centre */
    int empty;             /* no arc anywhere and no triangle near: no polygon */
} sw_leaf;

enum { LEAF_CLEAN = 0, LEAF_SPLIT = 1, LEAF_STAR = 2, LEAF_FAN = 3, LEAF_REFINE = 4,
       LEAF_CHORDS = 5 /* cut along several chords that do not cross in it */ };

struct sw_ctx {
    mfg_status st;
    mfg_prog *prog;        /* progress of the call (mfg_progress) */
    /* input in the axis frame */
    int64_t nv, nt;
    double *lx;            /* 3 * nv local coordinates */
    double *vr;            /* r of each vertex */
    sw_tri *tris;
    int64_t *tcurves;      /* 4 per triangle: its 3 edge curves and its silhouette (-1) */
    int64_t *gstart;       /* per triangle (nt + 1): its gap-closing curves in gcurves */
    int64_t *gcurves;
    int64_t *cstamp;       /* per curve, and per triangle (vstamp): dedup stamps */
    int64_t *vstamp;
    int64_t *hstamp;       /* per triangle: the stamp of the cell in which it is hidden */
    double theta;
    int full_turn;
    double tol, hmin;
    double quantum;        /* output weld distance */
    double ext;            /* the part's extent in the axis frame */
    int bounding_only;     /* cells look at the curves of bounding triangles only */
    int64_t coarse_blocks; /* blocks in cells above the finest size (a cut that failed) */
    hmap refine;           /* (level, ix, iz) of such cells: refined when the tree is
                              built again (analyse_cell) */
    int64_t leaf_cap;      /* a placement stops past this many leaves (0: no cap) ... */
    int capped;            /* ... and says so here */
    double origin[3], frame[3][3]; /* rows: e1, e2, axis */
    /* curves */
    sw_curve *curves;
    int64_t ncurves, capcurves;
    /* bins of triangles over (r, z) */
    int64_t nbr, nbz;
    double br0, bz0, bdr, bdz;
    int64_t *bin_start, *bin_items;
    /* per-call scratch */
    int64_t *stamp;
    int64_t stampv;
    int64_t *cand;
    int64_t ncand, capcand;
    /* circle scratch */
    double *xphi;
    int64_t *xtri;
    int *xentry;
    int64_t nx, capx;
    /* triangles crossed by sampled circles */
    int64_t *xpool;
    int64_t nxpool, capxpool;
    /* arc pool */
    sw_arc *arcs;
    int64_t narcs, caparcs;
    /* quadtree */
    int lmax;
    double h;              /* finest cell size */
    double r0, z0;         /* grid origin */
    int64_t nroot_r, nroot_z;
    sw_leaf *leaves;
    int64_t nleaves, capleaves;
    int64_t *leaf_curves;
    int64_t nleaf_curves, capleaf_curves;
    hmap corners;          /* leaf corners (ix, iz) */
    hmap leafmap;          /* (level, ix, iz) -> leaf */
    /* decomposition */
    sw_vtx2 *v2;
    int64_t nv2, capv2;
    hmap v2map;
    int64_t *poly_verts;
    int64_t npv, cappv;
    sw_poly *polys;
    int64_t npolys, cappolys;
    /* output */
    double *ox;            /* 3 * nout */
    int64_t nout, capout;
    hmap outmap;           /* exact coordinates -> vertex */
    int64_t *otri;
    int64_t notri, capotri;
    int64_t *oring;        /* per triangle: its edge along a circle (walls), else -1 -1 */
    int64_t caporing;
    double *odir;          /* per triangle: the wall's direction off that circle */
    int64_t capodir;
    int64_t *oface;        /* per triangle: a face piece's plane (2 tri + exit), else -1 */
    int64_t capoface;
};

static inline int ctx_nomem(sw_ctx *c)
{
    if (c->st == MFG_OK)
        c->st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    return 0;
}

/* Progress: one work unit (done of total) of the current stage; 0 (with c->st set to
 * MFG_ERR_CANCELLED) when the callback asked to stop. */
static inline int sw_poll(sw_ctx *c, double done, double total)
{
    if (mfg_prog_poll(c->prog, done, total))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

static inline int sw_stage(sw_ctx *c, const char *stage, double lo, double hi, int64_t every)
{
    if (mfg_prog_stage(c->prog, stage, lo, hi, every))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

/* A report inside a stage at its fraction q (0 .. 1), between steps that are not split
 * further. */
static inline int sw_report(sw_ctx *c, double q)
{
    if (mfg_prog_report(c->prog, q, 1.0))
        return 1;
    if (c->st == MFG_OK)
        c->st = mfg_prog_fail(c->prog);
    return 0;
}

/* Work units between progress reports: a quadtree cell analysed (~5-50 us), a leaf cut
 * into polygons (~2-20 us), a polygon's walls built (~2-20 us). */
#define SWEEP_EVERY_CELLS 512
#define SWEEP_EVERY_LEAVES 2048
#define SWEEP_EVERY_POLYS 2048

static inline double v_r(double x, double y)
{
    return sqrt(x * x + y * y);
}

/* qsort order of records by a double key, then an int64 tie-break (the comparators of
 * polygons.c and wallmesh.c). */
static inline int sw_cmp_key(double ka, double kb, int64_t ia, int64_t ib)
{
    if (ka != kb)
        return (ka > kb) - (ka < kb);
    return (ia > ib) - (ia < ib);
}

/* Named tolerances (the values of the single-file rotsweep.c).  None is the user's
 * tolerance: they absorb the rounding of separately computed doubles, each scaled by the
 * size it is relative to. */
/* Rounding allowance relative to a length scale (r + |z|, the part's extent, a cell side):
 * far above double rounding (~1e-16), far below anything the tolerance resolves. */
/* Tolerance limits at unit scale (rotsweep.c, the entry): at least 2^12 ulps of the
 * largest coordinate and 2^-24 of the part's extent; at most 1/16 of it (coarser
 * requests are computed to 1/16). */
#define SW_TOL_MIN_ULPS_LOG2 12
#define SW_TOL_MIN_REL_LOG2 (-24)
#define SW_TOL_MAX_UNIT 0.0625
#define SW_EPS_REL 1e-9
/* The same allowance on a curve or segment parameter in [0, 1] (a crossing at an end). */
#define SW_EPS_PARAM 1e-9
/* Two angles (radians) computed separately are one below this; hidden blocks are widened
 * by half of it on each side, so gaps narrower than it close. */
#define SW_EPS_ANGLE 1e-9
#define SW_EPS_ANGLE_HALF 5e-10
/* Angles equal up to rounding of a few ulps of 2 pi (a wall's lines that meet). */
#define SW_EPS_ANGLE_ROUND 1e-12
/* An angle within this of 2 pi is a full turn (mfgeom.h: "within 1e-12 of 2 pi"). */
#define SW_FULL_TURN_EPS 1e-12
/* Relative rounding of a sum of a few products (plane equations, cell coordinates). */
#define SW_EPS_ROUND 1e-12
/* Angular rounding margin per unit of (extent / distance from the axis). */
#define SW_EPS_ANGLE_EXT 1e-13
/* A fraction of the user's tolerance that counts as no distance (welds, empty segments). */
#define SW_TOL_FRAC 1e-6
/* A mesh vertex lifted onto its own triangle snaps to itself within this part of the
 * tolerance (plus SW_TOL_FRAC of its radius). */
#define SW_TOL_SNAP 0.01
/* Two planes are parallel when the squared sine of their angle is below this (1e-8^2). */
#define SW_EPS_SIN2 1e-16
/* A triangle whose normal's horizontal part is below this fraction of the normal faces
 * along the axis: no circle crosses its plane (sw_tri.vertical_ok). */
#define SW_EPS_HORIZ 1e-14
/* A cell nearer than this fraction of the extent to the axis hides nothing (mark_hidden). */
#define SW_EPS_AXIS_DIST 1e-7
/* The swept volume may fall short of the input's volume by this fraction (rounding). */
#define SW_EPS_VOLUME 1e-9

/* The distance within which two points of the meridian half-plane near (r, z) are one:
 * the rounding of coordinates of size r + |z| plus SW_TOL_FRAC of the tolerance.  Curve
 * points, chord ends and lifted corners are matched with it. */
static inline double sw_point_eps(const sw_ctx *c, double r, double z)
{
    return SW_EPS_REL * (r + fabs(z)) + SW_TOL_FRAC * c->tol;
}

typedef struct sw_out {
    double *phi;           /* angle of each output vertex */
    int64_t capphi;
    hmap lifts;            /* (v2, tri, sigma, exit) -> vertex */
} sw_out;

typedef struct wline {
    int side;              /* 0: the polygon on the left of u -> v, 1: on the right */
    int isend;
    int64_t arc;
    int64_t va, vb;        /* output vertices over u and over v */
    double pa, pb;         /* their angles, pb unwrapped to within pi of pa */
    int cancelled;         /* the same line on both sides: no wall along it */
} wline;

typedef struct wend {
    int64_t v2;            /* 2-D vertex, or -1: an event point (ring = evring) */
    int64_t ring_first, ring_n;
    double r, z;
    int64_t lo, hi;        /* vertices bounding the strip on this circle */
} wend;

typedef struct wstrip {
    wend e[2];
    int full;              /* a whole turn (no lines) */
    int left_covers;       /* the polygon on the left covers the strip */
    double span_mid;       /* its angular width half-way: the ends' widths are taken
                              within pi of it (a width of -1e-17 is 0, not 2 pi) */
} wstrip;

typedef struct sw_walls {
    wstrip *strips;
    int64_t nstrips, capstrips;
    /* ring entries at 2-D vertices: (v2, vertex) */
    int64_t *rv2, *rvid;
    int64_t nring, capring, capring2;
    int64_t *ring_start;   /* per v2, after sorting: entries [ring_start[v], ring_start[v+1]) */
    int64_t *evring;       /* vertices of event circles */
    int64_t nevring, capevring;
    char *push;            /* per 2-D vertex: its circle carries an outer wall, whose
                              grid vertices go out to circumscribe the circle */
    int64_t cappush;
    hmap evlists;          /* (poly, edge, line, 0) -> index in evl */
    int64_t *evl;
    int64_t nevl, capevl;
} sw_walls;

/* A curve through a cell and its crossings with the cell's sides. */
#define SW_MAXJUNCTION 16
typedef struct sw_jcurve {
    int64_t curve;
    int ncr;
    double pts[8][2];
} sw_jcurve;

typedef struct sw_iv {
    double a, b; /* unwrapped: a in [0, 2 pi), b > a */
} sw_iv;

/* setup.c */
void sw_make_frame(sw_ctx *c, const double *p, const double *a);
int sw_add_curve(sw_ctx *c, const double *a, const double *b, int64_t t0, int64_t t1,
                 int64_t va, int64_t vb);
void sw_edge_at_z(const sw_ctx *c, int64_t i, int64_t j, double z, double out[3]);
/* sweep/canonical.c: copies of the mesh in canonical order (vertices by coordinates,
 * triangles rotated to their smallest vertex and sorted); 0 when out of memory. */
int sw_canonical_input(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                       double **out_xyz, int64_t **out_tris);
int sw_setup(sw_ctx *c, const double *xyz, const int64_t *tris, const int64_t *nb);
int sw_build_bins(sw_ctx *c, double rmax, double zmin, double zmax);
int sw_gather(sw_ctx *c, double ra, double rb, double za, double zb);

/* gaps.c */
int sw_build_gap_curves(sw_ctx *c);

/* circles.c */
int sw_point_inside(sw_ctx *c, double r, double z, double psi);
int sw_push_arc(sw_ctx *c, const sw_arc *a);
int sw_circle_arcs(sw_ctx *c, double r, double z, sw_struct *out);
int sw_cmp_double_asc(const void *pa, const void *pb);
int sw_same_struct(const sw_ctx *c, const sw_struct *a, const sw_struct *b);

/* cells.c */
double sw_grid_r(const sw_ctx *c, int64_t i);
double sw_grid_z(const sw_ctx *c, int64_t i);
int sw_solve_quadratic(double a, double b, double c, int clamp, double roots[2]);
int sw_curve_side(const sw_curve *cv, int rside, double val, double lo, double hi,
                  double pos[2], double us[2]);
void sw_side_geom(const sw_ctx *c, int64_t ix, int64_t iz, int64_t s, int k, int *rside,
                  double *val, double *lo, double *hi);
int sw_corner_sample(sw_ctx *c, hmap *cache, int64_t ix, int64_t iz, sw_struct **pool,
                     int64_t *npool, int64_t *cappool, int64_t *out);
double sw_curve_sag(const sw_curve *cv, double ua, double ub);
int sw_same_pair(double pts[][2], double q[2][2], double eps);
double sw_curve_r(const sw_curve *cv, double u);
double sw_curve_u_at_r(const sw_curve *cv, double r, double lo, double hi);
int sw_crossing_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                     double rb, double za, double zb, const double *ua, int64_t cb,
                     const double *ub);
int sw_junction_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                     double rb, double za, double zb, const sw_jcurve *jc, int njc);
int sw_chords_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                   double rb, double za, double zb, const sw_jcurve *jc, int njc,
                   double peps);

/* hidden.c */
int sw_cmp_iv(const void *pa, const void *pb);
int sw_mark_hidden(sw_ctx *c, const sw_struct *centre, double ra, double rb, double za,
                   double zb, int64_t vs);

/* quadtree.c */
int sw_build_quadtree(sw_ctx *c);

/* polygons.c */
int sw_build_polygons(sw_ctx *c);

/* lift.c */
int64_t sw_out_vertex(sw_ctx *c, sw_out *o, const double p[3], double phi);
int64_t sw_ring_vertex(sw_ctx *c, sw_out *o, const sw_vtx2 *w, double phi);
int64_t sw_lift(sw_ctx *c, sw_out *o, int64_t iw, const sw_end *en, int isexit);
int sw_emit_tri_ring(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t ring_a, int64_t ring_b,
                     double dir);
int sw_emit_tri(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t tri, int isexit);
int64_t sw_ring_steps(const sw_ctx *c, double r);

/* walls.c */
int sw_edge_walls(sw_ctx *c, sw_out *o, sw_walls *W, int64_t u, int64_t v, int64_t P,
                  int64_t ip, int64_t Q, int64_t iq);

/* wallmesh.c */
int sw_emit_strips(sw_ctx *c, sw_out *o, sw_walls *W);
int sw_emit_faces(sw_ctx *c, sw_out *o, sw_walls *W);

/* pinches.c */
int sw_resolve_pinches(sw_ctx *c, sw_out *o);

/* shells.c */
double sw_mesh_volume(const double *xyz, const int64_t *tris, int64_t n);
int sw_drop_nested_shells(sw_ctx *c, int *overlap);
int sw_flip_out_slivers(sw_ctx *c);
int sw_cancel_twins(sw_ctx *c);
int sw_merge_faces(sw_ctx *c);
int sw_build_walls(sw_ctx *c, sw_out *o);

#endif /* MFG_SWEEP_SWEEP_H */
