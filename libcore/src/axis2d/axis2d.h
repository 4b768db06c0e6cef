/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/axis2d.h - internal header of the axis2d family: the medial axis of a planar face
 * by ridge tracing.  The context (ma_ctx), the boundary elements, the BVH and bisector types
 * and the functions shared between the family's files:
 *
 *   bvh.c          the BVH over the segments and its queries
 *   bisector.c     element distances, bisectors of element pairs
 *   trace.c        exact events along a bisector, the trace of one branch
 *   junctions.c    junctions and their ports, the junction registry, run_branch
 *   assemble.c     the result: short branches contracted, canonical order
 *   medial_axis.c  input checks and the entry point
 *
 * Method (design: docs/design/axis2d.md, section 2 and the lessons of section 7).  The elements
 * of the boundary are its edges as open segments (with the inward normal) and its reflex
 * vertices as points; convex vertices are the leaves of the axis (radius 0).  The axis is
 * a union of bisectors of element pairs: segment-segment (a line, or the midline of two
 * parallel edges), point-segment (a parabola), point-point (a line).  A trace starts at a
 * leaf and follows the bisector of its pair.  The bisector's point and radius are
 * polynomials of degree <= 2 in its parameter, so the first contact of every other element
 * with the moving disc (|p - v| = r for a reflex vertex, |n . (p - a)| = r with the foot
 * inside the open edge) is a root of a quadratic: exact in closed form.  The first event
 * is found by a best-first branch and bound over a BVH of the edges (node capsules give a
 * closed-form lower bound of their first contact).  At an event every element touching
 * the disc is gathered, sorted by the angle of its foot point, and each angularly
 * consecutive pair that is not (segment, its own endpoint) is a port -- a branch leaving
 * the junction.  Where the foot of a segment element leaves the open segment at a reflex
 * vertex (again a closed-form root), the element is switched to that vertex (a
 * transition along the branch, not a junction).  Junctions joined by a branch shorter
 * than tol are then contracted, and the result is put in canonical order (assemble).
 *
 * History: the first version advanced conservatively on a clearance margin that measured
 * an edge whose foot lies beyond its ends as +inf -- not a lower bound of the clearance --
 * so on needle spikes a step could jump over a contact (false leaves), and it scanned all
 * edges per step (1 000 segments: 2 s).  Now, on jittered needle stars with 16 holes
 * (bench/bench_medial_axis.py, 2 shared cores): 1 000 segments 12-17 ms, 10 000
 * 0.16-0.28 s, 100 000 1.2-2.0 s, i.e. 0.6-1.3 x Boost's Voronoi construct() on the same
 * segments, with the same topology.  The crossing check uses the same index. */
#ifndef MFG_AXIS2D_AXIS2D_H
#define MFG_AXIS2D_AXIS2D_H

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "common/predicates.h"

/* ---- growable arrays ------------------------------------------------------------- */
typedef struct { double *v; int64_t n, cap; } dvec;
typedef struct { int64_t *v; int64_t n, cap; } ivec;

/* Appends x to the growable array a (dvec or ivec) through mfg_grow: 1, or 0 when memory runs
 * out (a unchanged). */
#define MA_VEC_PUSH(a, x)                                                                  \
    (mfg_grow((void **)&(a)->v, &(a)->cap, (a)->n + 1, sizeof *(a)->v)                     \
         ? ((a)->v[(a)->n++] = (x), 1)                                                     \
         : 0)

static inline int dvec_push(dvec *a, double x) { return MA_VEC_PUSH(a, x); }
static inline int ivec_push(ivec *a, int64_t x) { return MA_VEC_PUSH(a, x); }

/* ---- the boundary elements ------------------------------------------------------- */
typedef struct {
    int64_t ns;                 /* segments: element ids 0 .. ns-1 */
    double *ax, *ay, *ux, *uy, *nx, *ny, *len;
    int64_t *prev, *next;       /* neighbouring segments in the ring */
    int64_t *orig;              /* caller's vertex index of the segment's start */
    int8_t *reflex, *convex;    /* of the vertex at the segment's start */
    int64_t *velem;             /* vertex k -> its element id (ns + j) or -1 */
    int64_t nv;                 /* reflex vertex elements: ids ns .. ns+nv-1 */
    int64_t *vk;                /* element ns+j -> vertex (segment start) index */
    double diag;
} ma_elems;

/* ---- the spatial index: a BVH over the segments ------------------------------------ */
/* Every clearance query (events, junction gathers, the crossing check) goes through this
 * one index.  A node holds a run of consecutive segments of one ring order (split in
 * halves: O(n), balanced, depth <= 1 + log2 n): consecutive edges of a boundary are near
 * each other, so a node is a compact piece of boundary -- and a bundle of thin needles (a
 * dense star) stays a thin fan, where a split of midpoints along an axis mixes needles of
 * different directions.  Each node has a box (for range queries) and a capsule (for the
 * event search, whose bounds it makes tight around thin fans).  A reflex vertex element
 * is reached through the segment that starts at it. */
typedef struct {
    int64_t nn;           /* nodes; node 0 is the root */
    double *box;          /* 4 per node: xmin, ymin, xmax, ymax */
    double *cap;          /* 5 per node: capsule axis (ax, ay)-(bx, by), radius */
    int64_t *kid;         /* 2 per node: children, or -1 and the leaf's first segment */
    int64_t *cnt;         /* segments of a leaf (0 for an inner node) */
    int64_t *end;         /* one past the last segment under the node */
    int64_t *beg;         /* the first segment under the node */
    const double *x, *y;  /* the segments: s from (x[s], y[s]) to (x[nxt[s]], y[nxt[s]]) */
    const int64_t *nxt;
} ma_bvh;

typedef struct {
    int64_t j;      /* junction */
    int64_t e1, e2; /* element pair of the bisector leaving it */
    double angle;   /* direction of the port */
    int used;
} ma_port;

typedef struct {
    double x, y, r;
    int64_t first_elem, nelem, first_port, nport;
    int64_t hnext;     /* next junction in its hash bucket */
    int64_t first_pos; /* its elements' ring positions, sorted, in ma_ctx.jpos (-1: not yet) */
} ma_junction;

/* The pocket a branch from a junction port runs into.  A junction's disc is empty and
 * splits the face: the branch between two elements a, b consecutive by foot angle only
 * sees the part beyond the arc between their feet - bounded by the boundary chain from a
 * to b that holds no other element of the junction, and holding perhaps whole other
 * rings.  So its event search looks at the ring positions from .. from + len (cyclic in
 * the ring [lo, hi); a position is a segment and the vertex it starts at) and at every
 * other ring.  Without it a junction touching n elements (a ring of 10^5 vertices on a
 * circle: its centre) cost O(n) per port, O(n^2) in all, and the other n - 2 elements,
 * touching the start disc to rounding, gave spurious events (self-loops at the centre). */
typedef struct {
    int active;
    int64_t lo, hi, from, len;
} ma_window;

typedef struct {
    ma_elems E;
    double tol, eps, gather, arrive;
    dvec px, py, pr;          /* samples */
    ivec boff, bend;          /* branch offsets (start of each branch), ends 2 per branch */
    ma_junction *J;
    int64_t nj, capj;
    ma_port *P;
    int64_t np, capp;
    ivec jelem;               /* element ids of the junctions */
    ivec jpos;                /* ring positions of the junctions' elements (first_pos) */
    const int64_t *roff;      /* the cleaned rings: segments roff[r] .. roff[r + 1] - 1 */
    int64_t nrings;
    ma_window win;            /* the current branch's pocket (event_search) */
    int64_t corner[2];        /* TR_CORNER: the segments meeting at the corner */
    ivec stack;               /* ports to trace */
    int8_t *reached;          /* convex vertices reached by a branch */
    ma_bvh T;                 /* the spatial index over the segments */
    ivec cand;                /* scratch: segments returned by the index */
    double *heapk;            /* scratch: the branch and bound's heap (keys, nodes) */
    int64_t *heapn;
    int64_t *hhead, hmask;    /* junction hash: buckets of a grid of cell `arrive` */
    double hx0, hy0;
} ma_ctx;

static inline int is_seg(const ma_elems *E, int64_t e) { return e < E->ns; }

/* ---- bisectors ------------------------------------------------------------------- */
enum { MA_PAR, MA_LL, MA_PL, MA_PP };
typedef struct {
    int kind;
    int64_t e1, e2;
    double Px, Py, dx, dy, r0, qx, qy, sg;
    double ax, ay, ux, uy, nx, ny, fx, h, x0; /* point-segment: the segment's frame */
    double v1x, v1y;                          /* point-point: one of the points */
    /* p(t) = p0 + p1 t + p2 t^2 and (not MA_PP) r(t) = r0c + r1c t + r2c t^2: the event
     * and window equations below are at most quadratic in t.  (fpx, fpy): the pair's
     * reflex vertex (MA_PL, MA_PP), for which r = |p - f|. */
    double p0x, p0y, p1x, p1y, p2x, p2y, r0c, r1c, r2c, fpx, fpy;
} ma_bis;

/* Named tolerances (the values of the single-file medial_axis.c); those with "diag" are
 * relative to the boundary's bounding-box diagonal (ma_elems.diag). */
/* The BVH's bounds are padded by this (diag): rounding of boxes and capsules. */
#define MA_EPS_PAD 1e-10
/* A junction gathers the elements within this (diag) of its disc: they touch it to
 * rounding (~1e-15 diag); wider picks up near elements that do not touch. */
#define MA_EPS_GATHER 1e-11
/* An arriving trace finds its junction within this (diag), a grazing element's near-double
 * root being less precise; also the radius above which a corner's end is not a leaf. */
#define MA_EPS_ARRIVE 1e-6
/* The crossing check: two boundary segments nearer than this (diag) touch. */
#define MA_EPS_TOUCH 1e-9
/* The step (diag) a trace takes past a window transition to see which side it is on. */
#define MA_EPS_STEP 1e-9
/* Two unit normals: their difference's squared length below this is no difference. */
#define MA_EPS_NORMAL2 1e-24
/* Two edges are parallel when the cross product of their unit normals is below this. */
#define MA_EPS_PARALLEL 1e-12
/* Relative rounding of a capsule radius (a sum of a few products). */
#define MA_EPS_ROUND 1e-12
/* A positive floor for a length that is divided by or must not be zero. */
#define MA_TINY 1e-300

/* Where a trace starts: a point of the axis (x, y) with its radius r, the element pair
 * (e1, e2) whose bisector it follows, and its direction (dx, dy). */
typedef struct {
    double x, y, r;
    int64_t e1, e2;
    double dx, dy;
} ma_start;

/* TR_CORNER: an event at a convex corner the trace passed with its disc growing (the
 * next segment there grazes the disc: ma_ctx.corner holds the two segments). */
enum { TR_LEAF, TR_EVENT, TR_NOMEM, TR_STUCK, TR_BADPAIR, TR_MISSED, TR_CORNER };

/* bvh.c */
int ma_bvh_build(ma_bvh *T, const double *x, const double *y, const int64_t *nxt, int64_t n);
void ma_bvh_free(ma_bvh *T);
double ma_pt_seg_d2(double px, double py, double ax, double ay, double bx, double by);
int ma_bvh_collect(const ma_bvh *T, const double seg[4], double rad, int64_t from, ivec *out);

/* bisector.c */
void ma_vpoint(const ma_elems *E, int64_t e, double *x, double *y);
double ma_elem_dist(const ma_elems *E, int64_t e, double x, double y);
int ma_own_pair(const ma_elems *E, int64_t a, int64_t b);
void ma_bis_make(const ma_elems *E, ma_bis *b, const ma_start *s);
void ma_bis_at(const ma_bis *b, double t, double *x, double *y, double *r);
double ma_bis_max_step(const ma_bis *b, double ta, double tb, double tol);
int ma_bis_split_at(const ma_bis *b, double ta, double tb, double tol, double *t_split);
void ma_bis_tangent(const ma_bis *b, double t, double *tx, double *ty);
int ma_bis_window(const ma_elems *E, const ma_bis *b, double x, double y, int64_t *which);
int64_t ma_window_switch(const ma_elems *E, int64_t e, int how);

/* junctions.c */
mfg_status ma_run_branch(ma_ctx *C, const ma_start *s, int64_t j0);

/* trace.c */
int ma_trace(ma_ctx *C, const ma_start *s, int first, double ev[5], int64_t *leafv);

/* assemble.c */
mfg_status ma_assemble(const ma_ctx *C, struct mfg_medial_axis **out);

#endif /* MFG_AXIS2D_AXIS2D_H */
