/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* assembly.h - private: the stages that turn the leaves' sheet soup and junction points
 * into an mfg_medial (docs/design/medial.md sections 4.1 - 4.3).  One file per stage:
 *   junction_search.c    the leaves where >= 4 elements may touch, their points merged
 *   sheet_assembly.c     sheets as connected components of one pair's triangles, made
 *                        coarse; pinholes closed; sheets narrower than the tolerance
 *   seam_assembly.c      the soup's seam segments chained, snapped, thinned; degenerate
 *                        seams from the rank-2 points
 *   junction_recovery.c  the junctions the leaf search missed, found where seams end
 *   medial.c             the entry point, the public result tables and mfg_medial_free
 * Every order is a sort on geometry or element ids, so the result is bit-identical for any
 * thread count and triangle order. */
#ifndef MFG_MEDIAL_ASSEMBLY_H
#define MFG_MEDIAL_ASSEMBLY_H

#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

/* Worker threads at most (the junction search; the octree and sheets have their own). */
#define MD_MAX_THREADS 64

/* What every assembly stage reads: the elements and their BVH, the leaf side, the tolerance
 * and the mode.  Built once the octree is known (h is its leaf side). */
typedef struct md_asm {
    const md_elements *el;
    const md_bvh *bvh;
    double h;     /* leaf side */
    double reach; /* 2 h: how far a seam end snaps to a junction, pieces join, ends meet */
    double tol;   /* the caller's tolerance */
    int full;     /* 1 full mode (every non-incident pair), 0 major (disjoint closures) */
} md_asm;

/* Junctions merged and sorted by point (merge_junctions), as the seams snap to them. */
typedef struct md_jset {
    const md_junction *v;
    int64_t n;
} md_jset;

/* ---- small helpers (shared by the stages) --------------------------------------------- */

static inline int md_cmp_xyz(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Lexicographic order where coordinates within d count as equal: a seam along x = 30
 * has ends whose x differ by an ulp, and its direction must not hang on that. */
static inline int md_cmp_xyz_tol(const double *a, const double *b, double d)
{
    for (int k = 0; k < 3; k++)
        if (fabs(a[k] - b[k]) > d)
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Is the sorted list a (na) a subset of the sorted list b (nb)? */
static inline int md_subset_of(const int64_t *a, int64_t na, const int64_t *b, int64_t nb)
{
    int64_t j = 0;
    for (int64_t i = 0; i < na; i++) {
        while (j < nb && b[j] < a[i])
            j++;
        if (j == nb || b[j] != a[i])
            return 0;
        j++;
    }
    return 1;
}

/* Lexicographic order of two sorted element sets (a shorter prefix first). */
static inline int md_cmp_set(const int64_t *a, int64_t na, const int64_t *b, int64_t nb)
{
    for (int64_t k = 0; k < na && k < nb; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return (na > nb) - (na < nb);
}

/* A pair in the output: major mode, disjoint closures; full mode, not incident. */
static inline int md_output_pair(const md_elements *el, int64_t a, int64_t b, int full)
{
    return full ? !md_incident(el, a, b) : !md_adjacent(el, a, b);
}

/* Does the set hold an output pair? */
static inline int md_set_has_output_pair(const md_elements *el, const int64_t *s, int64_t n,
                                         int full)
{
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = i + 1; j < n; j++)
            if (md_output_pair(el, s[i], s[j], full))
                return 1;
    return 0;
}

/* Growable arrays (every failure is out of memory). */
typedef struct dbuf {
    double *v;
    int64_t n, cap;
} dbuf;
typedef struct ibuf {
    int64_t *v;
    int64_t n, cap;
} ibuf;

static inline int dbuf_push(dbuf *b, double x)
{
    if (!mfg_grow((void **)&b->v, &b->cap, b->n + 1, sizeof *b->v))
        return 0;
    b->v[b->n++] = x;
    return 1;
}

static inline int ibuf_push(ibuf *b, int64_t x)
{
    if (!mfg_grow((void **)&b->v, &b->cap, b->n + 1, sizeof *b->v))
        return 0;
    b->v[b->n++] = x;
    return 1;
}

/* A polyline under construction: 3 coordinates and a radius per point. */
typedef struct polyline {
    dbuf pts, rad;
} polyline;

static inline int polyline_push(polyline *pl, const double *x, double r)
{
    return dbuf_push(&pl->pts, x[0]) && dbuf_push(&pl->pts, x[1]) && dbuf_push(&pl->pts, x[2]) &&
           dbuf_push(&pl->rad, r);
}

void md_polyline_reverse(polyline *pl);

/* Distance from p to the polyline P (n points). */
double md_polyline_dist(const double *P, int64_t n, const double *p);

/* ---- junction_search.c ------------------------------------------------------------------ */

/* All junction and degenerate-seam points of the leaves, in leaf order (design 4.3). */
mfg_status md_find_junctions(const md_asm *ax, const md_leaves *lv, int nthreads,
                             md_junction **out, int64_t *nout, mfg_prog *prog);

/* Junction order: by element set (size, then ids), then by point. */
int md_cmp_junction(const void *pa, const void *pb);
int md_same_set(const md_junction *a, const md_junction *b);

/* Merges the rank-3 points in place (design 4.3 step 3); returns the count kept, sorted by
 * point. */
int64_t md_merge_junctions(const md_asm *ax, md_junction *J, int64_t n);

/* The junction within reach of p whose set holds s (ascending, n), the nearest; -1 if
 * none. */
int64_t md_snap_junction(const md_jset *J, const double *p, const int64_t *s, int64_t n,
                         double reach);

/* ---- sheet_assembly.c ------------------------------------------------------------------- */

struct sheet_ref;
struct tri_key;

/* The sheet assembly's working state (freed as a whole by md_asm_free); the seam assembly
 * reads vsheet. */
typedef struct asm_state {
    int64_t *vsheet;   /* soup vertex -> output sheet, or -1 */
    int64_t *parent;   /* union-find over soup triangles */
    struct tri_key *keys;
    struct sheet_ref *refs;
    int64_t *vlocal;   /* soup vertex -> local index in its sheet */
} asm_state;

void md_asm_free(asm_state *s);

/* The sheets of the soup into m (design 4.1). */
mfg_status md_build_sheets(const md_asm *ax, const md_soup *sp, mfg_medial *m, asm_state *s,
                           mfg_prog *prog);

/* Closes the holes of a sheet narrower than tol / 4. */
mfg_status md_close_pinholes(mfg_medial *m, double tol);

/* Removes the sheets' zero-area triangles (a corner within eps of its opposite side)
 * without opening them: each is dropped and its neighbour across that side split at the
 * corner. */
mfg_status md_drop_needles(mfg_medial *m, double eps);

/* ---- seam_assembly.c -------------------------------------------------------------------- */

/* Elements of a seam set at most (more: the segment keeps its own 3). */
#define SEAM_EMAX 8

/* The output seams under construction. */
typedef struct seam_out {
    int64_t n;
    ibuf kinds, pt_off, el_off, elems, ends;
    dbuf pts, rad;
} seam_out;

void md_seam_out_free(seam_out *o);

/* Seams chained but not yet emitted: their ends are snapped only once every junction is
 * known (md_recover_junctions adds the ones the leaf search missed). */
typedef struct pend_seam {
    polyline pl;
    int64_t e[SEAM_EMAX];
    int32_t ne, kind;
} pend_seam;

typedef struct pend_list {
    pend_seam *v;
    int64_t n, cap;
} pend_list;

void md_pend_free(pend_list *pl);

/* Appends a finished polyline as a seam of the set (ns ids) and kind: ends snapped to J,
 * thinned.  0 on NOMEM. */
int md_emit_seam(const md_asm *ax, const md_jset *J, seam_out *o, polyline *pl,
                 const int64_t *set, int64_t ns, int32_t kind);

/* The seams of the soup (design 4.2) into out, those along the first ndeg seams of o (the
 * degenerate ones) left out.  0 on NOMEM. */
int md_soup_seams(const md_asm *ax, const md_soup *sp, const asm_state *s, const seam_out *o,
                  int64_t ndeg, pend_list *out);

/* Degenerate seams from the rank-2 points P (np, reordered) into o.  0 on NOMEM. */
int md_degenerate_seams(const md_asm *ax, md_junction *P, int64_t np, const md_jset *J,
                        seam_out *o);

/* Drops the sheets that lie within the tolerance of their own seams (sheet_assembly.c). */
mfg_status md_drop_narrow_sheets(const seam_out *o, double tol, mfg_medial *m);

/* ---- junction_recovery.c ---------------------------------------------------------------- */

/* The junctions the leaf search missed, found where seams end (design 4.3, recovery):
 * *J (*nj, merged and sorted by point) is replaced by a new array with them merged in
 * (the caller frees it when it differs from its own, also after a failure).  1, or 0 on
 * NOMEM. */
int md_recover_junctions(const md_asm *ax, pend_list *pl, md_junction **J, int64_t *nj);

#endif
