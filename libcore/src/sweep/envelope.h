/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/envelope.h - The rotational swept volume, second design (issue 20; the geometry
 * and why it holds: docs/design/sweep.md, "Second design").
 *
 * SV = union over t in [0, theta] of R(t) O is the region where the winding number of a
 * closed chain E is at least one, E = F + R(theta) B + S:
 *   F  the parts of O's boundary where a circle about the axis enters O (n . tau <= 0,
 *      tau(p) = k x p the velocity of the turn), kept at t = 0;
 *   B  the parts where it leaves (n . tau >= 0), turned by theta;
 *   S  the contour C = boundary of F swept from 0 to theta.
 * S is replaced by strips between polylines of the contour's vertices: on the side where
 * SV lies outside the circle (the contour edge rises along the axis) the polyline of
 * tangents (circumscribed: its apexes M_i p = R(t_i + delta/2) p / cos(delta/2)), on the
 * other side the chords (inscribed) - each displaced towards the strip's front, which
 * only adds to the winding number: the result holds SV (conservative) and lies within
 * the tolerance of it (tight: the apex height r (sec(delta/2) - 1) plus the twist of a
 * strip quad).  Where the two kinds of polyline meet at a contour vertex, flat "fins"
 * between them keep the chain closed.  The boundary of {w >= 1} is then evaluated exactly
 * by the arrangement (arrange/), and its planar pieces merged.
 *
 * Files:
 *   turn.c      the frame, the steps, turned points and tangent apexes (snapped to the
 *               arrangement's grid)
 *   contour.c   F and B: each triangle split along its line n . tau = 0, the contour,
 *               the pieces triangulated (F at t = 0, B turned by theta)
 *   profile.c   a full turn: the outline of the profile, revolved instead of the contour
 *   strips.c    the strips along the contour and the fins
 *   surface.c   the arrangement of the chain, the planar pieces merged, the output mesh
 *   canonical.c the input in a canonical order
 *   rotsweep.c  the entry point
 */
#ifndef MFG_SWEEP_ENVELOPE_H
#define MFG_SWEEP_ENVELOPE_H

#ifdef ARR_DEBUG /* the debugging prints of arrange/ and sweep/ */
#include <stdio.h>
#include <stdlib.h>
#endif
#include <stdint.h>

#include "arrange/arrange.h"
#include "common/hashmap.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "common/vec3.h"

/* The smallest tolerance accepted: 2^12 ulps of the largest coordinate and 2^-24 of the
 * part's extent about the axis point (a finer one asks for what the coordinates cannot
 * resolve, or for work without bound). */
#define SW_TOL_MIN_ULPS_LOG2 12
#define SW_TOL_MIN_REL_LOG2 (-24)
/* A part smaller than 2^-36 of its extent about the axis point (the unit) is refused: the
 * arrangement's grid (2^-50 of the unit) would resolve it by fewer than 2^14 steps, and
 * far below that it collapses to a point (the fuzzer: an octahedron of size 3 with its
 * axis point 1.6e60 away came out with no triangles). */
#define SW_PART_MIN_REL_LOG2 (-36)
/* ... and one smaller than 2^14 cells of the caller's grid (2^-50 of its largest
 * coordinate, where the passes after the turn round) likewise. */
#define SW_PART_MIN_CELLS_LOG2 14
/* A tolerance above 1/16 of the unit extent is computed to 1/16 (a tighter result keeps
 * the contract; coarser strips would leave the apexes far outside the unit box). */
#define SW_TOL_MAX_UNIT 0.0625
/* Angles within this of 2 pi mean a full turn (mfgeom.h). */
#define SW_FULL_TURN_EPS 1e-12
/* The tolerance's shares: the apex height (or chord sag) of the polylines, and the twist
 * of a strip quad (its two diagonals' distance); the rest is headroom for rounding. */
#define SW_SHARE_APEX 0.5
#define SW_SHARE_TWIST 0.375
#define SW_SHARE_PUSH 0.0625
/* cos / sin of a step angle closer than this to 0 are taken as exactly 0 (and the other
 * as +-1): a turn by a rounded pi/2 is then exact about a coordinate axis, so the turned
 * faces of a box stay in their planes. */
#define SW_TRIG_SNAP 1e-15
/* A vertex closer than this to the axis (unit scale) is on it: its turns are itself. */
#define SW_ON_AXIS 0x1p-40
/* Heights along the axis this close are one (rotsweep.c, level_heights), in runs no
 * wider than SW_LEVEL_SPAN (unit scale; far below the smallest tolerance, 2^-24). */
#define SW_LEVEL 0x1p-40
#define SW_LEVEL_SPAN 0x1p-38
/* A corner closer than this to its triangle's line f = 0 (unit scale) is on it
 * (contour.c, classify): the line is taken through the corner instead of cutting the
 * sides an ulp-sized sliver away from it. */
#define SW_CUT_SNAP 0x1p-40
/* Builds of the soup tried before a broken invariant is reported (rotsweep.c): the
 * first SW_ATTEMPTS arrange in the axis frame, the last SW_CALLER_ATTEMPTS in the
 * caller's axes from the first pass (surface.c, sw_env.caller_first). */
#define SW_ATTEMPTS 3
#define SW_CALLER_ATTEMPTS 2
/* The most soup triangles a sweep may build (strips x steps): beyond, the tolerance is
 * refused as needing work without bound. */
#define SW_MAX_SOUP 40000000

/* Kinds of the polylines a contour vertex sweeps. */
enum { SW_TANGENT = 0, SW_CHORD = 1 };

typedef struct sw_env {
    /* the soup's vertices: the input's (unit scale, about the axis point, on the grid),
     * then the points made here */
    double *x;
    int64_t nv, capv;
    int64_t nin;            /* input vertices (the first nin) */
    const int64_t *tri;     /* input triangles */
    int64_t nt;
    const int64_t *nb;      /* input triangle neighbours (mfg_mesh_require_closed) */
    double k[3];            /* the axis direction as given (exact predicates) */
    double frame[3][3];     /* rows u1, u2, axis: the axis frame (rotsweep.c) */
    double origin[3];       /* the axis point at unit scale: frame -> caller's = F^T x + it */
    int out_exp;            /* the result's grid: caller's unit coordinates times 2^-out_exp */
    double kh[3];           /* unit axis (rotations) */
    double theta, tol;
    double theta_asked;     /* the angle asked for (theta may become a full turn) */
    double tol_asked;       /* the tolerance asked for (tol may be less: turn.c) */
    int full_turn;
    int nsteps;             /* N: chord polylines have N segments, tangent ones N + 1 */
    double delta;           /* the step: t_i = i delta for i < N, t_N = theta */
    int symmetry;           /* the part's symmetry about the axis the steps follow (1: none) */
    int attempt;            /* 0, then 1, 2 when the soup is built again (one step more each) */
    int caller_first;       /* the soup is turned to the caller's axes before the first pass */
    const double *cx;       /* the input's vertices at unit scale in the caller's axes */
    double rmax;
    hmap turned;            /* (vertex, code) -> turned vertex */
    /* the soup: triangles and their planar group (-1: none) */
    int64_t *st;
    int64_t nst, capst;
    int64_t *sgroup;
    int64_t ngroups;
    /* the contour, pieces after the twist split: directed edges u -> v and their kind */
    int64_t *ce;
    int8_t *ckind;
    int64_t nce, capce;
    mfg_prog *prog;
    mfg_status st_code;
} sw_env;

/* ---- canonical.c ------------------------------------------------------------------------- */
/* A copy of the mesh numbered canonically (vertices by coordinates, triangles rotated to
 * their smallest vertex and sorted): malloc'd *out_xyz, *out_tris; 0 when out of memory. */
int sw_canonical_input(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                       double **out_xyz, int64_t **out_tris);

/* ---- turn.c ---------------------------------------------------------------------------- */
/* Snapped to the arrangement's grid (arrange/implicit.h). */
double sw_snap(double x);
/* Appends a vertex (snapped); its id, -1 when out of memory. */
int64_t sw_add_vertex(sw_env *e, const double p[3]);
/* The axis (unit direction) and the steps for theta and the tolerance (rmax set). */
void sw_setup_steps(sw_env *e);
/* t_i: i delta, theta for i >= N. */
double sw_step_angle(const sw_env *e, int i);
/* Vertex v turned by step i of the chord polyline (i = 0 .. N: R(i delta) v; R(theta) v
 * at i = N, v itself at a full turn), or apex i of the tangent polyline (i = 0 .. N-1).
 * Made once per (v, kind, i).  -1 when out of memory. */
int64_t sw_chord_point(sw_env *e, int64_t v, int i);
int64_t sw_apex_point(sw_env *e, int64_t v, int i);
/* Track point j of v's polyline of the given kind: chord j = 0 .. N, tangent j = 0 ..
 * N + 1 (v, the apexes, R(theta) v). */
int64_t sw_track_point(sw_env *e, int64_t v, int kind, int j);
static inline int sw_track_len(const sw_env *e, int kind)
{
    return kind == SW_TANGENT ? e->nsteps + 2 : e->nsteps + 1;
}
/* Distance of p from the axis (rounded). */
double sw_radius(const sw_env *e, const double p[3]);

/* ---- the soup --------------------------------------------------------------------------- */
/* Appends soup triangle (a, b, c) of planar group g (-1: none); 0 when out of memory. */
int sw_emit(sw_env *e, int64_t a, int64_t b, int64_t c, int64_t g);

/* ---- contour.c ---------------------------------------------------------------------------- */
/* F at t = 0 and R(theta) B, and the contour (split into pieces for the twist). */
int sw_build_faces(sw_env *e);
/* Appends contour piece u -> v of the given kind (SW_TANGENT, SW_CHORD, -1: level, the
 * kind decided by its neighbours); 0 when out of memory. */
int sw_add_contour_piece(sw_env *e, int64_t u, int64_t v, int kind);

/* ---- profile.c ------------------------------------------------------------------------------ */
/* A full turn: the contour replaced by the outline of the profile P (the soup must hold no
 * F or B faces). */
int sw_build_profile(sw_env *e);

/* ---- strips.c ------------------------------------------------------------------------------ */
/* The strips along the contour, and the fins where its polylines change kind. */
int sw_build_strips(sw_env *e);

/* ---- surface.c ----------------------------------------------------------------------------- */
/* The boundary of {w >= 1} of the soup as a closed triangle mesh at unit scale (about the
 * axis point): *ox (3 per vertex), *ot (3 per triangle), malloc'd. */
int sw_surface(sw_env *e, double **ox, int64_t *nox, int64_t **ot, int64_t *not_);

#endif
