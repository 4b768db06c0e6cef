/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect.h - private to the maximum / level / minimum intersection of spherical sets
 * (Ha 2001, seed 000 section 4): the prepared sets, the sweep's intervals and events,
 * the candidates and the work area shared by
 *   maxisect_sets.c     the input checked and prepared; membership of a direction
 *   maxisect_sweep.c    edge intervals and the ownership sweep along an edge
 *   maxisect_search.c   branch and bound over cells of the sphere
 *   maxisect_regions.c  regions of the best cover sets, and the result
 *   maxisect.c          the entry points. */
#ifndef MFG_MAXISECT_H
#define MFG_MAXISECT_H

#include <stdint.h>

#include "common/mfg_internal.h"
#include "sphere/sphere.h"

/* Coverage tolerance (radians): a set contains the directions within this distance; a
 * POLYGON contains x when x.n >= -TOL for each inward edge normal n (its edges moved out
 * by TOL), which reaches further beyond a sharp vertex (maxisect_sets.c, bounding_cap). */
#define TOL MFG_SPHERE_TOL

/* Slack in the cosine comparisons of bounding caps (which only ever skip work): far
 * above the rounding of a dot product of unit vectors (~1e-16). */
#define CAP_SLACK_COS 1e-12

/* Caps are widened by this much (radians), beyond the tolerance's reach, so the float
 * tests that skip far sets or cells never skip one within the coverage tolerance. */
#define CAP_WIDEN 1e-9

/* A region thinner than this (radians; 10 TOL) is the arc or point it thickens, and a
 * candidate direction this close to a region already built belongs to it. */
#define REGION_REACH (10 * TOL)

/* One input set, prepared. */
typedef struct sset {
    int kind, closed;
    int64_t id, nv;
    double w;
    double *v;     /* nv unit vertices */
    double *n;     /* POLYGON: inward unit normal of edge k (v[k] -> v[k+1]) */
    double cc[3];  /* bounding cap: centre and angular radius (cos, sin kept) */
    double cr, cos_cr, sin_cr;
    double ic[3], ir;  /* POLYGON: inscribed circle (centre, radius; ir = 0 if none) */
    double cos_ir, sin_ir;
    double *fan;   /* large POLYGON: bearing of each vertex about ic (the fan of ic) */
} sset;

/* The part [lo, hi] of an arc's parameter s inside set `set`. */
typedef struct interval {
    double lo, hi;
    int64_t set;
} interval;

/* An end of an interval, for the sweep along the arc. */
typedef struct event {
    double s;
    int start; /* 1 = start, 0 = end */
    int64_t set;
} event;

/* A candidate region: its cover set (sorted set indices) and a sample direction. */
typedef struct cand {
    double weight;
    int64_t off, len;  /* cover set in the pool of set indices; len < 0: not computed */
    uint64_t hash;     /* of the cover set, once computed */
    double x[3];
    int degenerate;    /* found only at an isolated point of an edge */
} cand;

/* Everything one call works with: the prepared sets, the sweep's buffers, the
 * candidates with their pool of cover sets, and the best weight found so far. */
typedef struct work {
    sset *sets;
    int64_t nsets;
    interval *iv;
    event *ev;
    int64_t cap_iv;
    /* candidate pool */
    cand *cands;
    int64_t ncands, cap_cands;
    int64_t *pool;
    int64_t npool, cap_pool;
    double best;
    int mode; /* MODE_MAX, MODE_LEVEL or MODE_MIN */
    int scale_exp; /* weights are the caller's times 2^-scale_exp (scale_weights) */
    double eps;    /* weights closer than this are equal */
    int64_t ncells; /* cells the search took from its queue (its work, for the tests) */
    mfg_prog *prog; /* progress of the call (never NULL after mfg_maxisect_run set it) */
} work;

/* What a call looks for: the maximum, every local maximum >= a level, the minimum. */
enum { MODE_MAX, MODE_LEVEL, MODE_MIN };

/* ---- The fan of a large polygon: O(log v) membership and O(log v + k) clipping ----
 *
 * A convex polygon is the union of the triangles (ic, v_k, v_k+1) about an interior
 * point ic: the lune between the half meridians from ic through v_k and v_k+1 meets the
 * polygon exactly where it meets the half-space of edge k.  The bearings of the vertices
 * about ic increase with k, so the triangle holding a direction is found by binary
 * search, and an arc, whose bearing about ic is monotone, only crosses the triangles
 * between those of its ends: only their edges can clip it.  Neighbouring edges (FAN_PAD
 * on each side) are tested too, so a direction within the tolerance of a vertex is
 * treated exactly as by the test against every edge. */
#define FAN_MIN_VERTICES 32 /* below this, testing every edge is as fast */
#define FAN_PAD 2

/* The input of the three entry points: npolys sets (vertices 3 each, ring offsets, kinds,
 * closed flags, weights; closed and weights may be NULL), as in mfgeom.h. */
typedef struct ms_input {
    const double *vertices;
    const int64_t *offsets;
    const int32_t *kinds;
    const int32_t *closed;
    int64_t npolys;
    const double *weights;
} ms_input;

/* ---- maxisect.c ------------------------------------------------------------------- */

/* The entry points' common body (mode MODE_MAX, MODE_LEVEL or MODE_MIN); when ncells is
 * not NULL it receives the number of cells the search examined (W.ncells), also on
 * error, so tests can bound the work without timing it. */
mfg_status mfg_maxisect_run(int mode, const ms_input *in, double level, mfg_regions **out,
                            int64_t *ncells);
/* The same with progress (mfg_progress, may be NULL); call names the entry point. */
mfg_status mfg_maxisect_run_p(int mode, const ms_input *in, double level, mfg_regions **out,
                              int64_t *ncells, const mfg_progress *progress, const char *call);

/* ---- maxisect_sets.c -------------------------------------------------------------- */

mfg_status mfg_sets_prepare(const ms_input *in, work *W);
void mfg_sets_free(work *W);
/* Parameter s of direction y on the arc a -> b (x(s) = a + s (b - a)); 0 when y is off
 * the arc beyond the tolerance. */
int mfg_param_on_edge(const double *a, const double *b, const double *y, double *s);
/* Is direction y in set S (within TOL)? */
int mfg_set_contains(const sset *S, const double *y);
/* Index k of the fan triangle (ic, v_k, v_k+1) of S holding y (S->fan set). */
int64_t mfg_fan_locate(const sset *S, const double *y);

/* ---- maxisect_sweep.c -------------------------------------------------------------- */

/* The arc a -> b's bounding cap: centre mc, half length and its cos and sin. */
void mfg_edge_cap(const double *a, const double *b, double mc[3], double *half, double *ch,
                  double *sh);
/* Caps apart: angle(mc, cc) > half + cr, compared through cosines. */
static inline int mfg_caps_apart(const double mc[3], double half, double ch, double sh,
                             const sset *S)
{
    return half + S->cr < MFG_PI && mfg_dot3(mc, S->cc) < ch * S->cos_cr - sh * S->sin_cr - CAP_SLACK_COS;
}
/* Interval [lo, hi] of s on the arc a -> b inside polygon S; 0 when empty. */
int mfg_polygon_interval(const sset *S, const double *a, const double *b, double *lo, double *hi);
/* Intervals of the arc a -> b inside thin (EDGE or POINT) set S (index sid), written to
 * iv (room for 2 per piece of S); returns their count. */
int64_t mfg_thin_intervals(const sset *S, int64_t sid, const double *a, const double *b,
                           interval *iv);
/* Intervals of the arc a -> b inside the listed sets (own excluded), into W->iv. */
int64_t mfg_edge_intervals(work *W, int64_t own, const double *a, const double *b,
                           const int64_t *list, int64_t nlist);
/* qsort order of events: by s, starts before ends (closed sets touch). */
int mfg_cmp_event(const void *x, const void *y);
/* Computes candidate ci's cover set into the pool. */
mfg_status mfg_compute_cover(work *W, int64_t ci);
/* Records a candidate direction x of the given weight. */
mfg_status mfg_add_candidate(work *W, double weight, const double x[3], int degenerate);
/* The part [r0, r1] of the arc a -> b (x(s) = a + s (b - a); a == b: a point). */
typedef struct arc_span {
    const double *a, *b;
    double r0, r1;
} arc_span;
/* What a sweep records: pieces and points whose weight reaches the running best W->best
 * (keep_best, which then rises) or threshold, less eps. */
typedef struct sweep_goal {
    double threshold;
    int keep_best;
    double eps;
} sweep_goal;
/* Sweeps span (an arc of set own, or -1) over the listed sets from the ownership base,
 * recording the pieces and points that reach the goal. */
mfg_status mfg_sweep_edge(work *W, int64_t own, const arc_span *span, double base,
                          const int64_t *list, int64_t nlist, const sweep_goal *goal);

/* ---- maxisect_search.c ------------------------------------------------------------- */

/* Branch and bound over cells of the sphere: the candidates of the mode's best weight
 * (MODE_MAX), of weight >= threshold (MODE_LEVEL) or of least weight (MODE_MIN). */
mfg_status mfg_cell_search(work *W, int mode, double threshold, double eps);

/* ---- maxisect_regions.c ------------------------------------------------------------ */

/* The regions of the candidates, as the caller's result. */
mfg_status mfg_regions_of(work *W, int maximal_only, double level, double eps, mfg_regions **out);

#endif
