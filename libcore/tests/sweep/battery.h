/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* battery.h - the pieces of the rotational sweep battery (test_sweep_battery.c) shared by
 * its files: a seeded generator, growable meshes, one sweep problem, the inputs' families,
 * a bounding volume hierarchy for distance and exact point-in-solid queries, and the
 * checks of a result (conservative, tight, near another solid). */
#ifndef MFG_SWEEP_BATTERY_H
#define MFG_SWEEP_BATTERY_H

#include <stdint.h>

#include "mfgeom.h"

/* ------------------------------------------------------------------------ */
/* A seeded generator (splitmix64): every input is a function of its seed     */
/* ------------------------------------------------------------------------ */

typedef struct bt_rng {
    uint64_t s;
} bt_rng;

static inline uint64_t bt_next(bt_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* uniform in [lo, hi) from the top 53 bits */
static inline double bt_unif(bt_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(bt_next(r) >> 11) * 0x1p-53);
}

/* uniform integer in [lo, hi] */
static inline int64_t bt_int(bt_rng *r, int64_t lo, int64_t hi)
{
    return lo + (int64_t)(bt_next(r) % (uint64_t)(hi - lo + 1));
}

/* ------------------------------------------------------------------------ */
/* Growable indexed triangle meshes                                         */
/* ------------------------------------------------------------------------ */

typedef struct bt_mesh {
    double *xyz;
    int64_t *tri;
    int64_t nv, nt, cap_v, cap_t;
} bt_mesh;

int64_t bt_add_vertex(bt_mesh *m, double x, double y, double z);
void bt_add_tri(bt_mesh *m, int64_t a, int64_t b, int64_t c);
void bt_mesh_free(bt_mesh *m);
/* A rotation drawn uniformly (a random unit quaternion's), row-major. */
void bt_random_rotation(bt_rng *r, double R[9]);
bt_mesh bt_mesh_copy(const bt_mesh *m);
/* appends src's vertices and triangles (another shell) */
void bt_mesh_append(bt_mesh *dst, const bt_mesh *src);
/* the library's view of it (no copy) */
mfg_mesh bt_as_mfg(const bt_mesh *m);
/* bounding box diagonal of the vertices */
double bt_diag(const double *xyz, int64_t nv);

/* ------------------------------------------------------------------------ */
/* One sweep problem                                                        */
/* ------------------------------------------------------------------------ */

typedef struct bt_problem {
    const char *family;
    uint64_t seed;
    char what[256]; /* how it was made: variant, placement, axis kind, angle kind */
    bt_mesh in;     /* the solid, placed */
    double ap[3], ad[3], angle, tol;
    double size;    /* the input's bounding box diagonal */
} bt_problem;

void bt_problem_free(bt_problem *p);

/* The families, in battery order; bt_make builds the problem of a family and seed
 * (everything, the variant, placement, axis, angle and tolerance, follows from the
 * seed).  Returns 0 when the family is unknown or its data file cannot be read. */
extern const char *const bt_families[];
extern const int bt_nfamilies;
/* the real parts' files in MFG_SWEEP_DATA_DIR (data/README.md: origin and licence) */
extern const char *const bt_part_files[];
extern const int bt_nparts;
int bt_make(const char *family, uint64_t seed, bt_problem *out);

/* Reference solids for the checks' self-tests: the region between an n-gon of vertex
 * radius ro and one of vertex radius ri about the z axis, from z0 to z1; a box. */
void bt_ring(bt_mesh *m, int n, double ri, double ro, double z0, double z1);
void bt_box(bt_mesh *m, const double lo[3], const double hi[3]);

/* OFF files: the real parts are read from MFG_SWEEP_DATA_DIR; failing inputs are
 * written (the OFF and a side file with axis, angle and tolerance) for reproduction. */
int bt_read_off(const char *path, bt_mesh *out);
int bt_write_problem(const char *dir, const char *tag, const bt_problem *p);

/* ------------------------------------------------------------------------ */
/* A bounding volume hierarchy over a triangle mesh                         */
/* ------------------------------------------------------------------------ */

typedef struct bt_node {
    double lo[3], hi[3];
    int64_t first, count; /* leaf: ids[first .. first + count); inner: count = 0 */
    int64_t right;        /* inner: the right child (the left one follows the node) */
} bt_node;

typedef struct bt_index {
    const double *V;
    const int64_t *T;
    int64_t nt;
    int64_t *ids;
    bt_node *nodes;
    int64_t nnodes;
    unsigned char *flat; /* zero-area triangles: no part in crossing counts */
    double box[6], diag;
} bt_index;

int bt_index_build(bt_index *ix, const double *V, const int64_t *T, int64_t nt);
void bt_index_free(bt_index *ix);
/* Distance from p to the surface (the nearest triangle in *nearest when not NULL). */
double bt_dist(const bt_index *ix, const double p[3], int64_t *nearest);
/* The triangles within radius of p (at most max of them, into ids): how many. */
int bt_near(const bt_index *ix, const double p[3], double radius, int64_t *ids, int max);
/* Exact: 1 when p is inside the closed mesh (odd number of crossings of a segment from p
 * to beyond the box, every crossing decided by exact orient3d), 0 outside, -1 when p
 * lies on a triangle or every tried segment met an edge or vertex. */
int bt_inside(const bt_index *ix, const double p[3]);
/* Signed distance, > 0 outside: |value| <= band is returned unsigned (p counts as on the
 * surface, its side is not needed).  *unsure is set when the side was not decided. */
double bt_signed(const bt_index *ix, const double p[3], double band, int64_t *nearest, int *unsure);

/* ------------------------------------------------------------------------ */
/* Checks of a result                                                       */
/* ------------------------------------------------------------------------ */

/* The settings of the checks (the battery and the self-tests use the same).
 * BT_EPS_REL: the allowance for floating-point rounding, relative to the part's size
 * about the axis (bt_allowance: input bounding box diagonal + the largest distance of an
 * input vertex from the axis).  Turned points, distances and the result's own
 * coordinates are rounded at ~1e-16 of it, so 1e-9 is rounding with a wide margin and far
 * below any tolerance the battery asks (>= 1e-4 of the size). */
#define BT_EPS_REL 1e-9
/* conservative: turned input points (a third corners, sides, faces), the distance queries
 * all their arcs may spend, and the most one arc may spend, before an arc counts as
 * checked at a coarser step than the fine one (reported, not a failure) */
#define BT_CONS_ARCS 240
/* conservative: an arc piece at most this many tolerances long is checked at its ends
 * only (the fine grid: "the arc between samples far below tol") */
#define BT_FINE_ARC_TOLS (1.0 / 16)
#define BT_CONS_EVALS 30000
#define BT_CONS_EVALS_PER_ARC 15000
/* tight: result vertices (all of them up to this many), face points, the distance
 * queries all of them may spend and the most one may spend before it counts as undecided */
#define BT_TIGHT_VERTICES 1000
#define BT_TIGHT_FACE_POINTS 300
#define BT_TIGHT_EVALS 100000
#define BT_TIGHT_EVALS_PER_POINT 20000
/* rigid motion: points of each result checked against the other */
#define BT_NEAR_POINTS 200

double bt_allowance(const bt_problem *p);

/* Conservative: points of the input surface turned by t in [0, angle] lie inside the
 * result or within eps of its surface. */
typedef struct bt_cons_report {
    long arcs, evals;
    long outside;        /* arcs with a sample farther than eps outside */
    long coarse;         /* arcs whose budget ran out above the fine step */
    double coarse_step;  /* the longest unchecked arc piece of those, in tolerances */
    double worst;        /* the farthest sample outside */
    double worst_t, worst_q[3];
    long unsure_side;    /* samples whose side was undecided (counted as on) */
} bt_cons_report;

void bt_check_conservative(const bt_problem *pb, const bt_index *res, double eps, int npoints, long evals,
                           long evals_per_arc, uint64_t seed, bt_cons_report *out);

/* Tight: points of the result lie within tol + eps of SV. */
typedef struct bt_tight_report {
    long points, within, beyond, undecided, evals;
    double worst_lb;     /* the largest certified lower bound of a point beyond */
    double worst_p[3];
    double undecided_lb; /* the largest lower bound left on an undecided point */
    double undecided_p[3], undecided_min; /* one of them, its smallest distance sampled */
} bt_tight_report;

void bt_check_tight(const bt_problem *pb, const bt_index *input, const mfg_mesh *res, double eps, int nvertices,
                    int nfacepoints, long evals, long evals_per_point, uint64_t seed, bt_tight_report *out);

/* Points of a (its vertices, sampled, and face points) within bound of the solid b:
 * returns how many are not; *worst gets the largest signed distance seen. */
long bt_within_solid(const mfg_mesh *a, const bt_index *b, double bound, int npoints, uint64_t seed,
                     double *worst);


/* ------------------------------------------------------------------------ */
/* The checks' own tests (battery_selftest.c): returns the number of failures  */
/* ------------------------------------------------------------------------ */

int bt_selftest(int verbose);

#endif
