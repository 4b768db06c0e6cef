/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheets.h - private to the sheet extraction stage (sheets.c: entry, unit buffers, threads,
 * merge; sheet_trim.c: the trim; sheet_tet.c: one Kuhn tetrahedron and one leaf):
 * the vertex keys, the work units and the state of one (leaf, pair).  See sheets.c. */
#ifndef MFG_MEDIAL_SHEETS_H
#define MFG_MEDIAL_SHEETS_H

#include <stdint.h>

#include "medial/medial.h"

/* Room per (leaf, pair): the 19 Kuhn edges of a cube, at most one boundary point per tet
 * face (18 distinct: 12 on the cube's faces, 6 inside), at most 2 corners per tet (12). */
#define MAX_PV 64
#define MAX_BP 48


/* A vertex key: the pair, and either one lattice edge (a vertex of the marching tets;
 * e[1] all -1, c = -2), or the two lattice edges of the polygon edge that holds a boundary
 * point (in a fixed order) and the element that trims it, or for a sheet corner (found in
 * one polygon only) the leaf's lattice point with direction 8 + tet, the cut's position
 * in the polygon, c = -3.  A lattice edge is its smaller lattice point (i, j, k) and its
 * Kuhn direction (1 .. 7: bit d set when it steps along axis d). */
typedef struct vkey {
    int64_t a, b;
    int32_t e[2][4];
    int64_t c;
} vkey;

typedef struct vrec {
    vkey k;
    double x[3];
    double r; /* D at the vertex */
} vrec;

/* One work unit's output, in leaf order; vertex indices are local to the unit. */
typedef struct unit_buf {
    vrec *v;
    int64_t nv, cv;
    int64_t *t, *tp; /* 3 vertices and the pair (a, b) per triangle */
    int64_t nt, ct;
    int64_t *s, *se, *sp; /* 2 vertices, 3 elements and the pair per seam segment */
    int32_t *sk;
    int64_t ns, cs;
    mfg_status st;
} unit_buf;

/* A vertex of a (leaf, pair): its record in the unit, its trim value and trimming
 * element, and its lattice edge (local corners lo < hi) or -1 for a boundary point. */
typedef struct pvert {
    int64_t rec;
    double tau;
    int64_t arg;
    int argk; /* the term of tau that arg belongs to: TRIM_A, TRIM_B, TRIM_NU, TRIM_OUT */
    int lo, hi;
} pvert;

enum { TRIM_A = 0, TRIM_B = 1, TRIM_NU = 2, TRIM_OUT = 3 };

/* Values at the leaf's centre of the element at one position of C, for Lipschitz bounds
 * over the leaf: g a face's in-plane margin (-inf: none), m the region margin, d the
 * carrier distance. */
typedef struct cbound {
    double g, m, d;
} cbound;

/* The state of one (leaf, pair). */
typedef struct ctx {
    const md_elements *el;
    const md_bvh *bvh; /* NULL: no inside test */
    int deep;          /* the leaf lies deeper than 2h inside the solid: no inside test */
    const int64_t *C;
    int nC;
    int64_t a, b;
    int ia, ib;        /* positions of a and b in C, or -1 */
    double ctr[3];     /* the leaf's centre */
    double sdc;        /* signed distance to the boundary there (with a BVH) */
    struct cbound *cb; /* per C position: bounds from ctr (NAN: not yet computed) */
    int capC;
    double cx[8][3];   /* corner c = dx | dy << 1 | dz << 2 */
    double h;
    int32_t cijk[8][3];
    double f[8];
    int slot[64];      /* lattice edge lo * 8 + hi -> pv index, or -1 */
    double ex[64][3];  /* lattice edge lo * 8 + hi -> its root, when bit lo * 8 + hi of */
    uint64_t have_ex;  /* have_ex is set */
    pvert pv[MAX_PV];
    int npv;
    int bpu[MAX_BP], bpv[MAX_BP], bpi[MAX_BP]; /* boundary points by polygon edge */
    int nbp;
    unit_buf *out;
    const struct md_leaf_index *li; /* the leaves by position (coarse leaves' neighbours) */
} ctx;

/* sheets.c: the order of vertex keys, and appending to a unit's buffers (-1 / 0 on NOMEM). */
int md_sheet_cmp_key(const vkey *x, const vkey *y);
int64_t md_sheet_push_vertex(unit_buf *u, const vkey *k, const double *x, double r);
int md_sheet_push_tri(unit_buf *u, int64_t p, int64_t q, int64_t r, int64_t a, int64_t b);
int md_sheet_push_seg(unit_buf *u, int64_t p, int64_t q, const int64_t *e3, int32_t kind, int64_t a,
                      int64_t b);

/* sheet_trim.c: the trim. */
double md_sheet_signed_dist(const ctx *c, const double *x);
int md_sheet_pair_shows(ctx *c);
int md_sheet_edge_vertex(ctx *c, int lo, int hi);
int md_sheet_boundary_point(ctx *c, int iu, int iv);
int md_sheet_corner_point(const ctx *c, const pvert *p, const pvert *q, double *x, double *Dout);

/* sheet_coarse.c: the leaves by (level, smallest lattice point), to find the leaf across a
 * coarse leaf's face (slot: leaf index or -1, cap a power of two; empty when no leaf is
 * coarse); built once per extraction, read by every thread. */
typedef struct md_leaf_index {
    int64_t *slot;
    int64_t cap;
    int32_t maxlevel;
} md_leaf_index;
int md_leaf_index_build(const md_leaves *lv, md_leaf_index *li); /* 0 on NOMEM */
void md_leaf_index_free(md_leaf_index *li);

/* sheet_coarse.c: the sheet of a coarse plane leaf (L->level > 0, design 3.4), into ub. */
mfg_status md_sheet_coarse_leaf(const md_elements *el, const md_leaves *lv,
                                const md_leaf_index *li, const md_leaf *L, unit_buf *ub);

/* sheet_tet.c: the marching tets and trim of every pair of one leaf, into ub (a coarse
 * plane leaf goes to md_sheet_coarse_leaf). */
mfg_status md_sheet_leaf(const md_elements *el, const md_bvh *bvh, const md_leaves *lv,
                         const md_leaf *L, unit_buf *ub, ctx *c);

#endif
