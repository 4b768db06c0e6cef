/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial.c - the medial surface's public entry point (issue 9; Lee & Lee, the medial
 * surface of a polyhedron; docs/design/medial.md): input checks, the pipeline elements ->
 * BVH -> octree leaves -> sheets (sheets.c) and junctions (junction_search.c) -> the
 * assembly into mfg_medial (sheet_assembly.c, seam_assembly.c, junction_recovery.c;
 * assembly.h), the public result tables and mfg_medial_free.
 *
 * Assembly (design 4.1 - 4.3):
 *   sheets     the connected components of one pair's triangles, made coarse (4.1);
 *   seams      the soup's seam segments chained per element set, snapped to the
 *              junctions, thinned; the degenerate seams from the rank-2 points (4.2);
 *   junctions  the rank-3 points merged, the ones the leaf search missed recovered where
 *              seams end (4.3);
 *   major/full the pairs of disjoint closures, or every non-incident pair.
 * Every order is a sort on geometry or element ids, so the result is bit-identical for any
 * thread count and triangle order. */
#define _GNU_SOURCE /* sysconf(_SC_NPROCESSORS_ONLN) */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "medial/assembly.h"

/* ---- the result tables ---------------------------------------------------------------------- */

/* Seam order: by element set, then first point. */
typedef struct seam_sort {
    const seam_out *o;
    int64_t idx;
} seam_sort;

static int cmp_seam(const void *pa, const void *pb)
{
    const seam_sort *a = pa, *b = pb;
    const seam_out *o = a->o;
    int64_t ea = o->el_off.v[a->idx], na = o->el_off.v[a->idx + 1] - ea;
    int64_t eb = o->el_off.v[b->idx], nb = o->el_off.v[b->idx + 1] - eb;
    for (int64_t i = 0; i < na && i < nb; i++)
        if (o->elems.v[ea + i] != o->elems.v[eb + i])
            return o->elems.v[ea + i] < o->elems.v[eb + i] ? -1 : 1;
    if (na != nb)
        return na < nb ? -1 : 1;
    int c = md_cmp_xyz(o->pts.v + 3 * o->pt_off.v[a->idx], o->pts.v + 3 * o->pt_off.v[b->idx]);
    if (c)
        return c;
    return (a->idx > b->idx) - (a->idx < b->idx);
}

static mfg_status seams_to_public(const seam_out *o, mfg_medial *m)
{
    int64_t n = o->n;
    m->nseams = n;
    int64_t np = o->rad.n, ne = o->elems.n;
    m->seam_kinds = malloc((size_t)(n + 1) * sizeof(int32_t));
    m->seam_point_offsets = malloc((size_t)(n + 1) * sizeof(int64_t));
    m->seam_element_offsets = malloc((size_t)(n + 1) * sizeof(int64_t));
    m->seam_points = malloc((size_t)(3 * np + 1) * sizeof(double));
    m->seam_radii = malloc((size_t)(np + 1) * sizeof(double));
    m->seam_elements = malloc((size_t)(ne + 1) * sizeof(int64_t));
    m->seam_ends = malloc((size_t)(2 * n + 1) * sizeof(int64_t));
    seam_sort *ord = malloc((size_t)(n + 1) * sizeof *ord);
    if (!m->seam_kinds || !m->seam_point_offsets || !m->seam_element_offsets || !m->seam_points ||
        !m->seam_radii || !m->seam_elements || !m->seam_ends || !ord) {
        free(ord);
        return MFG_ERR_NOMEM;
    }
    for (int64_t i = 0; i < n; i++)
        ord[i] = (seam_sort){o, i};
    if (n > 1)
        qsort(ord, (size_t)(n), sizeof *ord, cmp_seam);
    int64_t po = 0, eo = 0;
    m->seam_point_offsets[0] = 0;
    m->seam_element_offsets[0] = 0;
    for (int64_t k = 0; k < n; k++) {
        int64_t i = ord[k].idx;
        int64_t p0 = o->pt_off.v[i], p1 = o->pt_off.v[i + 1];
        int64_t e0 = o->el_off.v[i], e1 = o->el_off.v[i + 1];
        memcpy(m->seam_points + 3 * po, o->pts.v + 3 * p0, (size_t)(3 * (p1 - p0)) * sizeof(double));
        memcpy(m->seam_radii + po, o->rad.v + p0, (size_t)(p1 - p0) * sizeof(double));
        memcpy(m->seam_elements + eo, o->elems.v + e0, (size_t)(e1 - e0) * sizeof(int64_t));
        po += p1 - p0;
        eo += e1 - e0;
        m->seam_point_offsets[k + 1] = po;
        m->seam_element_offsets[k + 1] = eo;
        m->seam_kinds[k] = (int32_t)o->kinds.v[i];
        m->seam_ends[2 * k] = o->ends.v[2 * i];
        m->seam_ends[2 * k + 1] = o->ends.v[2 * i + 1];
    }
    free(ord);
    return MFG_OK;
}

/* ---- elements ---------------------------------------------------------------------------------- */

static mfg_status elements_to_public(const md_elements *el, mfg_medial *m)
{
    int64_t ne = el->nelements;
    m->nelements = ne;
    m->nfaces = el->nfaces;
    m->nedges = el->nedges;
    m->nvertices = el->nverts;
    m->ntriangles = el->nt;
    m->element_kinds = malloc((size_t)(ne + 1) * sizeof(int32_t));
    m->element_convex = malloc((size_t)(ne + 1) * sizeof(int32_t));
    m->face_of_triangle = malloc((size_t)(el->nt + 1) * sizeof(int64_t));
    m->face_planes = malloc((size_t)(4 * el->nfaces + 1) * sizeof(double));
    m->edge_segments = malloc((size_t)(6 * el->nedges + 1) * sizeof(double));
    m->vertex_points = malloc((size_t)(3 * el->nverts + 1) * sizeof(double));
    if (!m->element_kinds || !m->element_convex || !m->face_of_triangle || !m->face_planes ||
        !m->edge_segments || !m->vertex_points)
        return MFG_ERR_NOMEM;
    for (int64_t e = 0; e < ne; e++) {
        int k = md_kind(el, e);
        m->element_kinds[e] = k == MD_FACE ? MFG_ELEM_FACE : (k == MD_EDGE ? MFG_ELEM_EDGE : MFG_ELEM_VERTEX);
        m->element_convex[e] = k == MD_EDGE ? el->edge_convex[e - el->nfaces] : -1;
    }
    memcpy(m->face_of_triangle, el->face_of_triangle, (size_t)el->nt * sizeof(int64_t));
    memcpy(m->face_planes, el->face_plane, (size_t)(4 * el->nfaces) * sizeof(double));
    memcpy(m->edge_segments, el->edge_seg, (size_t)(6 * el->nedges) * sizeof(double));
    memcpy(m->vertex_points, el->vert_xyz, (size_t)(3 * el->nverts) * sizeof(double));
    return MFG_OK;
}

static mfg_status junctions_to_public(const md_junction *J, int64_t nj, mfg_medial *m)
{
    int64_t ne = 0;
    for (int64_t j = 0; j < nj; j++)
        ne += J[j].n;
    m->njunctions = nj;
    m->junction_kinds = malloc((size_t)(nj + 1) * sizeof(int32_t));
    m->junction_points = malloc((size_t)(3 * nj + 1) * sizeof(double));
    m->junction_radii = malloc((size_t)(nj + 1) * sizeof(double));
    m->junction_element_offsets = malloc((size_t)(nj + 1) * sizeof(int64_t));
    m->junction_elements = malloc((size_t)(ne + 1) * sizeof(int64_t));
    if (!m->junction_kinds || !m->junction_points || !m->junction_radii ||
        !m->junction_element_offsets || !m->junction_elements)
        return MFG_ERR_NOMEM;
    int64_t o = 0;
    m->junction_element_offsets[0] = 0;
    for (int64_t j = 0; j < nj; j++) {
        m->junction_kinds[j] = J[j].kind;
        memcpy(m->junction_points + 3 * j, J[j].x, sizeof J[j].x);
        m->junction_radii[j] = J[j].r;
        memcpy(m->junction_elements + o, J[j].elems, (size_t)J[j].n * sizeof(int64_t));
        o += J[j].n;
        m->junction_element_offsets[j + 1] = o;
    }
    return MFG_OK;
}

/* ---- the entry point ------------------------------------------------------------------------------ */

static int thread_count(int32_t nthreads)
{
    long n = nthreads;
    if (n == 0) {
        n = sysconf(_SC_NPROCESSORS_ONLN);
        if (n < 1)
            n = 1;
    }
    return (int)(n > MD_MAX_THREADS ? MD_MAX_THREADS : n);
}

mfg_status mfg_medial_surface(const double *xyz, int64_t nvertices, const int64_t *triangles,
                              int64_t ntriangles, double tolerance, uint32_t flags,
                              int32_t nthreads, mfg_medial **out)
{
    return mfg_medial_surface_p(xyz, nvertices, triangles, ntriangles, tolerance, flags,
                                nthreads, out, NULL);
}

/* Work units between progress reports (counted on the caller's thread only): an octree
 * unit (a cell at the work depth, ~0.1-1 ms), a unit of 16 leaves (~0.2-2 ms), a block of
 * 64 leaves searched for junctions (~0.1-1 ms). */
#define MEDIAL_EVERY_OCTREE 16
#define MEDIAL_EVERY_SHEETS 16
#define MEDIAL_EVERY_JUNCTIONS 16

mfg_status mfg_medial_surface_p(const double *xyz, int64_t nvertices, const int64_t *triangles,
                                int64_t ntriangles, double tolerance, uint32_t flags,
                                int32_t nthreads, mfg_medial **out,
                                const mfg_progress *progress)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "mfg_medial_surface: out is NULL");
    if (flags & ~MFG_MEDIAL_FULL)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: unknown flags 0x%x",
                        (unsigned)(flags & ~MFG_MEDIAL_FULL));
    if (nthreads < 0)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: nthreads %d < 0", (int)nthreads);
    int full = (flags & MFG_MEDIAL_FULL) != 0, nth = thread_count(nthreads);
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_medial_surface");
    if (!mfg_prog_stage(&prog, "medial: elements", 0, 0.05, 1))
        return mfg_prog_fail(&prog);
    md_elements el;
    mfg_status st = md_elements_build(xyz, nvertices, triangles, ntriangles, tolerance, &el);
    if (st != MFG_OK)
        return st;
    md_bvh *bvh = NULL;
    md_leaves lv;
    md_soup sp;
    md_junction *J = NULL, *Jall = NULL; /* Jall: J's rank-3 part, or a new array */
    int64_t nJ = 0, nall = 0;
    int own_jall = 0;
    pend_list pend;
    memset(&pend, 0, sizeof pend);
    memset(&lv, 0, sizeof lv);
    memset(&sp, 0, sizeof sp);
    asm_state as;
    memset(&as, 0, sizeof as);
    seam_out so;
    memset(&so, 0, sizeof so);
    mfg_medial *m = calloc(1, sizeof *m);
    const char *stage = "the result";
    if (!m) {
        st = MFG_ERR_NOMEM;
        goto cleanup;
    }
    stage = "the BVH";
    if ((st = md_bvh_build(&el, &bvh)) != MFG_OK)
        goto cleanup;
#define MEDIAL_STAGE(name, lo, hi, every)                                                  \
    do {                                                                                   \
        if (!mfg_prog_stage(&prog, name, lo, hi, every)) {                                 \
            st = mfg_prog_fail(&prog);                                                     \
            goto cleanup;                                                                  \
        }                                                                                  \
    } while (0)
/* A report inside the assembly (its steps are sequential and not split further). */
#define MEDIAL_STEP(done, total)                                                           \
    do {                                                                                   \
        if (!mfg_prog_report(&prog, done, total)) {                                        \
            st = mfg_prog_fail(&prog);                                                     \
            goto cleanup;                                                                  \
        }                                                                                  \
    } while (0)
    stage = "the octree";
    MEDIAL_STAGE("medial: octree", 0.05, 0.25, MEDIAL_EVERY_OCTREE);
    if ((st = md_octree_build_p(&el, bvh, tolerance, full, 1, nth, &lv, &prog)) != MFG_OK)
        goto cleanup;
    stage = "the sheets";
    MEDIAL_STAGE("medial: sheets", 0.25, 0.6, MEDIAL_EVERY_SHEETS);
    if ((st = md_sheets_extract_p(&el, bvh, &lv, tolerance, nth, &sp, &prog)) != MFG_OK)
        goto cleanup;
    double h = lv.lat.h;
    md_asm ax = {&el, bvh, h, 2 * h, tolerance, full};
    stage = "the junctions";
    MEDIAL_STAGE("medial: junctions", 0.6, 0.75, MEDIAL_EVERY_JUNCTIONS);
    if ((st = md_find_junctions(&ax, &lv, nth, &J, &nJ, &prog)) != MFG_OK)
        goto cleanup;
    stage = "the assembly";
    MEDIAL_STAGE("medial: assembly", 0.75, 1.0, 1);
    /* rank-2 points (degenerate seams) first, rank-3 after */
    int64_t n2 = 0;
    for (int64_t i = 0; i < nJ; i++)
        if (J[i].rank == 2) {
            md_junction t = J[n2];
            J[n2++] = J[i];
            J[i] = t;
        }
    /* J is NULL when no leaf found a point (J + 0 on NULL is undefined behaviour). */
    md_junction *J3 = J ? J + n2 : NULL;
    int64_t n3 = md_merge_junctions(&ax, J3, nJ - n2);
    Jall = J3;
    nall = n3;
    if ((st = elements_to_public(&el, m)) != MFG_OK || (st = md_build_sheets(&ax, &sp, m, &as, &prog)) != MFG_OK)
        goto cleanup;
    MEDIAL_STEP(1, 5);
    /* Degenerate seams first: the soup's seams along them are dropped.  The soup's seams
     * are chained, the junctions the leaves missed are found where they end
     * (recover_junctions), and only then is every seam emitted with its ends snapped; the
     * degenerate seams are emitted again for that (the first pass only says which soup
     * seams they cover). */
    md_jset J3s = {J3, n3};
    if (!md_degenerate_seams(&ax, J, n2, &J3s, &so) ||
        !md_soup_seams(&ax, &sp, &as, &so, so.n, &pend)) {
        st = MFG_ERR_NOMEM;
        goto cleanup;
    }
    MEDIAL_STEP(2, 5);
    int rec = md_recover_junctions(&ax, &pend, &Jall, &nall);
    own_jall = Jall != J3;
    if (!rec) {
        st = MFG_ERR_NOMEM;
        goto cleanup;
    }
    MEDIAL_STEP(3, 5);
    md_seam_out_free(&so);
    memset(&so, 0, sizeof so);
    md_jset Js = {Jall, nall};
    if (!md_degenerate_seams(&ax, J, n2, &Js, &so)) {
        st = MFG_ERR_NOMEM;
        goto cleanup;
    }
    for (int64_t i = 0; i < pend.n; i++)
        if (!md_emit_seam(&ax, &Js, &so, &pend.v[i].pl, pend.v[i].e, pend.v[i].ne, pend.v[i].kind)) {
            st = MFG_ERR_NOMEM;
            goto cleanup;
        }
    MEDIAL_STEP(4, 5);
    if ((st = md_drop_narrow_sheets(&so, tolerance, m)) != MFG_OK || (st = md_close_pinholes(m, tolerance)) != MFG_OK ||
        (st = md_drop_needles(m, MD_ROUND_REL * el.diag)) != MFG_OK ||
        (st = seams_to_public(&so, m)) != MFG_OK || (st = junctions_to_public(Jall, nall, m)) != MFG_OK)
        goto cleanup;
    MEDIAL_STAGE("medial: done", 1.0, 1.0, 1);
#undef MEDIAL_STAGE
#undef MEDIAL_STEP
    m->cells_visited = lv.cells_visited;
    m->leaves = lv.nleaves;
    m->leaf_size = h;
cleanup: /* also the way out on success (st MFG_OK) */
    md_seam_out_free(&so);
    md_pend_free(&pend);
    if (own_jall)
        free(Jall);
    md_asm_free(&as);
    free(J);
    md_soup_free(&sp);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
    if (st == MFG_OK) {
        *out = m;
        mfg_clear_error();
        return MFG_OK;
    }
    mfg_medial_free(m);
    if (st == MFG_ERR_NOMEM)
        return mfg_fail(MFG_ERR_NOMEM, "mfg_medial_surface: out of memory building %s", stage);
    return st; /* the stage's own detail stands */
}

void mfg_medial_free(mfg_medial *m)
{
    if (!m)
        return;
    free(m->element_kinds);
    free(m->element_convex);
    free(m->face_of_triangle);
    free(m->face_planes);
    free(m->edge_segments);
    free(m->vertex_points);
    free(m->sheet_elements);
    free(m->sheet_forms);
    free(m->sheet_vertex_offsets);
    free(m->sheet_triangle_offsets);
    free(m->sheet_vertices);
    free(m->sheet_radii);
    free(m->sheet_triangles);
    free(m->seam_kinds);
    free(m->seam_point_offsets);
    free(m->seam_points);
    free(m->seam_radii);
    free(m->seam_element_offsets);
    free(m->seam_elements);
    free(m->seam_ends);
    free(m->junction_kinds);
    free(m->junction_points);
    free(m->junction_radii);
    free(m->junction_element_offsets);
    free(m->junction_elements);
    free(m);
}
