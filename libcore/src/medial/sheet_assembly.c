/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheet_assembly.c - the medial surface's sheets (docs/design/medial.md section 4.1): the
 * connected components of one pair's triangles in the soup, vertices compacted; triangles
 * with a vertex off the pair's bisector (> 1e-9 L) and slivers (the square prism's side
 * pairs, trimmed to its axis) dropped; each sheet made coarse within the tolerance
 * (md_sheet_simplify).  Then, once the seams are known, the holes narrower than the
 * tolerance closed and the sheets lying within the tolerance of their own seams dropped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/hashmap.h"
#include "medial/assembly.h"

/* A component whose width (area / extent) is below this times the tolerance is a sliver,
 * not a sheet (the square prism's side pairs, trimmed down to its axis). */
#define SLIVER_WIDTH 1e-3

typedef struct sheet_ref {
    int64_t a, b;      /* the pair */
    int64_t first;     /* index into the sorted triangle list */
    int64_t ntri;
    double minxyz[3];  /* smallest vertex: the order among one pair's components */
} sheet_ref;

static int cmp_sheet(const void *pa, const void *pb)
{
    const sheet_ref *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->b != b->b)
        return a->b < b->b ? -1 : 1;
    return md_cmp_xyz(a->minxyz, b->minxyz);
}

/* Triangle order for grouping: by component root (its smallest triangle index). */
typedef struct tri_key {
    int64_t root, t;
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    if (a->root != b->root)
        return a->root < b->root ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

static double tri_area(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

void md_asm_free(asm_state *s)
{
    free(s->vsheet);
    free(s->parent);
    free(s->keys);
    free(s->refs);
    free(s->vlocal);
}

/* The output sheets' triangles grouped: s->parent, s->keys and s->refs filled (the
 * sheets' refs sorted by pair, then smallest vertex).  Returns the sheet count, or -1 on
 * NOMEM. */
static int64_t sheet_components(const md_asm *ax, const md_soup *sp, asm_state *s)
{
    const md_elements *el = ax->el;
    double h = ax->h, tol = ax->tol;
    int full = ax->full;
    int64_t nv = sp->nverts, nt = sp->ntris;
    s->vsheet = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    s->vlocal = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    s->parent = malloc((size_t)(nt ? nt : 1) * sizeof(int64_t));
    s->keys = malloc((size_t)(nt ? nt : 1) * sizeof(tri_key));
    s->refs = malloc((size_t)(nt ? nt : 1) * sizeof(sheet_ref));
    int64_t *first_tri = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    if (!s->vsheet || !s->vlocal || !s->parent || !s->keys || !s->refs || !first_tri) {
        free(first_tri);
        return -1;
    }
    for (int64_t v = 0; v < nv; v++) {
        s->vsheet[v] = -1;
        first_tri[v] = -1;
    }
    /* Triangles kept: of an output pair, not below 1e-6 h^2 (design 4.1). */
    double amin = MD_AREA_DROP * h * h;
    int64_t pa = -1, pb = -1;
    int pair_out = 0;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = sp->tris + 3 * t;
        if (sp->tri_pair[2 * t] != pa || sp->tri_pair[2 * t + 1] != pb) { /* runs of one pair */
            pa = sp->tri_pair[2 * t];
            pb = sp->tri_pair[2 * t + 1];
            pair_out = md_output_pair(el, pa, pb, full);
        }
        int keep = pair_out &&
                   tri_area(sp->xyz + 3 * tv[0], sp->xyz + 3 * tv[1], sp->xyz + 3 * tv[2]) >= amin;
        /* Design 4.1: every vertex equidistant from the pair at its radius within 1e-9 L.
         * A guard: a vertex that is not takes its triangles out rather than spoil the
         * result.  (The extraction's boundary fallback once put one 0.41 off the bisector
         * by the full L-bracket's corner (10, 10, 40); since face_root_near_chord and
         * seam_polish in sheets.c nothing is dropped on the test solids.) */
        for (int k = 0; k < 3 && keep; k++) {
            const double *p = sp->xyz + 3 * tv[k];
            double r = sp->radius[tv[k]];
            keep = fabs(md_dist_car(el, pa, p, NULL) - r) <= MD_ROUND_REL * el->diag &&
                   fabs(md_dist_car(el, pb, p, NULL) - r) <= MD_ROUND_REL * el->diag;
        }
        s->parent[t] = keep ? t : -1;
    }
    /* Components of one pair's triangles: triangles sharing a vertex (the soup welds a
     * vertex per (pair, lattice edge), so a vertex belongs to one pair). */
    for (int64_t t = 0; t < nt; t++) {
        if (s->parent[t] < 0)
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t v = sp->tris[3 * t + k];
            if (first_tri[v] < 0)
                first_tri[v] = t;
            else
                mfg_uf_union(s->parent, first_tri[v], t);
        }
    }
    free(first_tri);
    int64_t nk = 0;
    for (int64_t t = 0; t < nt; t++)
        if (s->parent[t] >= 0)
            s->keys[nk++] = (tri_key){mfg_uf_find(s->parent, t), t};
    if (nk > 1)
        qsort(s->keys, (size_t)(nk), sizeof *s->keys, cmp_tri_key);
    int64_t nref = 0;
    for (int64_t i = 0; i < nk;) {
        int64_t j = i;
        double area = 0, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        sheet_ref r;
        r.first = i;
        r.a = sp->tri_pair[2 * s->keys[i].t];
        r.b = sp->tri_pair[2 * s->keys[i].t + 1];
        for (int k = 0; k < 3; k++)
            r.minxyz[k] = INFINITY;
        while (j < nk && s->keys[j].root == s->keys[i].root) {
            const int64_t *tv = sp->tris + 3 * s->keys[j].t;
            area += tri_area(sp->xyz + 3 * tv[0], sp->xyz + 3 * tv[1], sp->xyz + 3 * tv[2]);
            for (int c = 0; c < 3; c++) {
                const double *p = sp->xyz + 3 * tv[c];
                if (md_cmp_xyz(p, r.minxyz) < 0)
                    memcpy(r.minxyz, p, sizeof r.minxyz);
                for (int k = 0; k < 3; k++) {
                    lo[k] = fmin(lo[k], p[k]);
                    hi[k] = fmax(hi[k], p[k]);
                }
            }
            j++;
        }
        r.ntri = j - i;
        /* Width ~ area / extent: slivers narrower than 1e-3 tolerance are not sheets
         * (the square prism's side pairs, trimmed down to its axis). */
        double ext = mfg_dist3(lo, hi);
        if (ext > 0 && area / ext >= SLIVER_WIDTH * tol)
            s->refs[nref++] = r;
        i = j;
    }
    if (nref > 1)
        qsort(s->refs, (size_t)(nref), sizeof *s->refs, cmp_sheet);
    return nref;
}

/* Each sheet made coarse within the tolerance (md_sheet_simplify: kept vertices stay
 * where the extraction put them, on the bisector; corners and seams stay), then moved
 * down over the room the sheets before it freed.  vlabel: the seam label of each sheet
 * vertex. */
static mfg_status simplify_sheets(const md_asm *ax, mfg_medial *m, const int64_t *vlabel,
                                  mfg_prog *prog)
{
    int64_t nref = m->nsheets;
    int64_t wv = 0, wt = 0, v0 = 0, t0 = 0;
    for (int64_t r = 0; r < nref; r++) {
        /* a report per sheet: the first fifth of the assembly */
        if (!mfg_prog_poll(prog, (double)r, 5.0 * (double)nref))
            return mfg_prog_fail(prog);
        int64_t v1 = m->sheet_vertex_offsets[r + 1], t1 = m->sheet_triangle_offsets[r + 1];
        md_sheet_mesh sh = {v1 - v0, m->sheet_vertices + 3 * v0, m->sheet_radii + v0, t1 - t0,
                            m->sheet_triangles + 3 * t0};
        mfg_status st = md_sheet_simplify(ax->el, m->sheet_elements[2 * r], m->sheet_elements[2 * r + 1],
                                          ax->tol, vlabel + v0, &sh, NULL);
        if (st != MFG_OK)
            return st;
        int64_t nvr = sh.nverts, ntr = sh.ntris;
        memmove(m->sheet_vertices + 3 * wv, m->sheet_vertices + 3 * v0, (size_t)(3 * nvr) * sizeof(double));
        memmove(m->sheet_radii + wv, m->sheet_radii + v0, (size_t)nvr * sizeof(double));
        memmove(m->sheet_triangles + 3 * wt, m->sheet_triangles + 3 * t0, (size_t)(3 * ntr) * sizeof(int64_t));
        m->sheet_vertex_offsets[r] = wv;
        m->sheet_triangle_offsets[r] = wt;
        wv += nvr;
        wt += ntr;
        v0 = v1;
        t0 = t1;
    }
    m->sheet_vertex_offsets[nref] = wv;
    m->sheet_triangle_offsets[nref] = wt;
    /* Give the freed room back (a failing shrink keeps the larger block). */
    double *dv = realloc(m->sheet_vertices, (size_t)(3 * wv + 1) * sizeof(double));
    if (dv)
        m->sheet_vertices = dv;
    double *dr = realloc(m->sheet_radii, (size_t)(wv + 1) * sizeof(double));
    if (dr)
        m->sheet_radii = dr;
    int64_t *dt = realloc(m->sheet_triangles, (size_t)(3 * wt + 1) * sizeof(int64_t));
    if (dt)
        m->sheet_triangles = dt;
    return MFG_OK;
}

mfg_status md_build_sheets(const md_asm *ax, const md_soup *sp, mfg_medial *m, asm_state *s,
                           mfg_prog *prog)
{
    const md_elements *el = ax->el;
    int64_t nv = sp->nverts;
    int64_t nref = sheet_components(ax, sp, s);
    if (nref < 0)
        return MFG_ERR_NOMEM;
    /* Counts, then the arrays. */
    int64_t totv = 0, tott = 0;
    for (int64_t r = 0; r < nref; r++) {
        tott += s->refs[r].ntri;
        for (int64_t i = s->refs[r].first; i < s->refs[r].first + s->refs[r].ntri; i++)
            for (int k = 0; k < 3; k++) {
                int64_t v = sp->tris[3 * s->keys[i].t + k];
                if (s->vsheet[v] < 0) {
                    s->vsheet[v] = r;
                    totv++;
                }
            }
    }
    m->nsheets = nref;
    m->sheet_elements = malloc((size_t)(2 * nref + 1) * sizeof(int64_t));
    m->sheet_forms = malloc((size_t)(nref + 1) * sizeof(int32_t));
    m->sheet_vertex_offsets = malloc((size_t)(nref + 1) * sizeof(int64_t));
    m->sheet_triangle_offsets = malloc((size_t)(nref + 1) * sizeof(int64_t));
    m->sheet_vertices = malloc((size_t)(3 * totv + 1) * sizeof(double));
    m->sheet_radii = malloc((size_t)(totv + 1) * sizeof(double));
    m->sheet_triangles = malloc((size_t)(3 * tott + 1) * sizeof(int64_t));
    if (!m->sheet_elements || !m->sheet_forms || !m->sheet_vertex_offsets ||
        !m->sheet_triangle_offsets || !m->sheet_vertices || !m->sheet_radii || !m->sheet_triangles)
        return MFG_ERR_NOMEM;
    /* Each sheet's vertices in ascending soup order (the soup's order is the lattice's). */
    int64_t to = 0;
    m->sheet_vertex_offsets[0] = 0;
    m->sheet_triangle_offsets[0] = 0;
    /* vertices of sheet r: scan the soup once, bucketed by sheet */
    int64_t *cnt = calloc((size_t)(nref + 1), sizeof(int64_t));
    int64_t *label = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    int64_t *vlabel = malloc((size_t)(totv ? totv : 1) * sizeof(int64_t));
    if (!cnt || !label || !vlabel) {
        free(cnt);
        free(label);
        free(vlabel);
        return MFG_ERR_NOMEM;
    }
    md_soup_seam_labels(sp, label);
    for (int64_t v = 0; v < nv; v++)
        if (s->vsheet[v] >= 0)
            cnt[s->vsheet[v] + 1]++;
    for (int64_t r = 0; r < nref; r++)
        cnt[r + 1] += cnt[r];
    for (int64_t r = 0; r <= nref; r++)
        m->sheet_vertex_offsets[r] = cnt[r];
    for (int64_t v = 0; v < nv; v++) {
        int64_t r = s->vsheet[v];
        if (r < 0)
            continue;
        int64_t at = cnt[r]++;
        s->vlocal[v] = at - m->sheet_vertex_offsets[r];
        memcpy(m->sheet_vertices + 3 * at, sp->xyz + 3 * v, 3 * sizeof(double));
        m->sheet_radii[at] = sp->radius[v];
        vlabel[at] = label[v];
    }
    free(cnt);
    free(label);
    for (int64_t r = 0; r < nref; r++) {
        const sheet_ref *R = &s->refs[r];
        m->sheet_elements[2 * r] = R->a;
        m->sheet_elements[2 * r + 1] = R->b;
        m->sheet_forms[r] = md_form(el, R->a, R->b);
        for (int64_t i = R->first; i < R->first + R->ntri; i++) {
            for (int k = 0; k < 3; k++)
                m->sheet_triangles[3 * to + k] = s->vlocal[sp->tris[3 * s->keys[i].t + k]];
            to++;
        }
        m->sheet_triangle_offsets[r + 1] = to;
    }
    mfg_status st = simplify_sheets(ax, m, vlabel, prog);
    free(vlabel);
    return st;
}

/* ---- pinholes -------------------------------------------------------------------------------- */

/* A directed side (u -> v) of a sheet triangle. */
typedef struct dside {
    int64_t u, v;
} dside;

static int cmp_dside_undirected(const void *pa, const void *pb)
{
    const dside *a = pa, *b = pb;
    int64_t a0 = a->u < a->v ? a->u : a->v, a1 = a->u < a->v ? a->v : a->u;
    int64_t b0 = b->u < b->v ? b->u : b->v, b1 = b->u < b->v ? b->v : b->u;
    if (a0 != b0)
        return a0 < b0 ? -1 : 1;
    if (a1 != b1)
        return a1 < b1 ? -1 : 1;
    return (a->u > b->u) - (a->u < b->u);
}

static int cmp_dside_from(const void *pa, const void *pb)
{
    const dside *a = pa, *b = pb;
    if (a->u != b->u)
        return a->u < b->u ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* Closes the holes of a sheet narrower than tol / 4 (the bounding-box diagonal of the
 * hole's boundary loop, or twice its area over its perimeter for a sliver; the sheet's
 * largest loop, its outline, never).  Rotated off the lattice,
 * the 64-segment cup's bottom sheet had a hole 0.003 wide (tolerance 0.64) where three
 * leaves' trimmed polygons do not quite meet: not a feature of the medial surface at
 * this tolerance, but a boundary with no seam along it.  A hole is closed by a fan of
 * triangles on its loop, oriented with the sheet, spanning points on the bisector across
 * less than the tolerance.  The new triangles go after the sheet's own. */
mfg_status md_close_pinholes(mfg_medial *m, double tol)
{
    int64_t maxt = 0;
    for (int64_t r = 0; r < m->nsheets; r++)
        if (m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r] > maxt)
            maxt = m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r];
    dside *sd = malloc((size_t)(3 * maxt + 1) * sizeof *sd);
    dside *bd = malloc((size_t)(3 * maxt + 1) * sizeof *bd);
    char *used = malloc((size_t)(3 * maxt + 1));
    int64_t *loop = malloc((size_t)(3 * maxt + 1) * sizeof *loop);
    int64_t *loop_off = malloc((size_t)(3 * maxt + 2) * sizeof *loop_off);
    ibuf fill = {0}; /* per new triangle: sheet, then its 3 local vertices */
    mfg_status st = MFG_OK;
    if (!sd || !bd || !used || !loop || !loop_off) {
        st = MFG_ERR_NOMEM;
        goto done;
    }
    for (int64_t r = 0; r < m->nsheets && st == MFG_OK; r++) {
        int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
        const double *V = m->sheet_vertices + 3 * m->sheet_vertex_offsets[r];
        int64_t ns = 0, nb = 0;
        for (int64_t t = t0; t < t1; t++)
            for (int k = 0; k < 3; k++)
                sd[ns++] = (dside){m->sheet_triangles[3 * t + k], m->sheet_triangles[3 * t + (k + 1) % 3]};
        if (ns > 1)
            qsort(sd, (size_t)ns, sizeof *sd, cmp_dside_undirected);
        for (int64_t i = 0; i < ns;) {
            int64_t j = i + 1;
            while (j < ns && !((sd[j].u < sd[j].v ? sd[j].u : sd[j].v) != (sd[i].u < sd[i].v ? sd[i].u : sd[i].v) ||
                               (sd[j].u < sd[j].v ? sd[j].v : sd[j].u) != (sd[i].u < sd[i].v ? sd[i].v : sd[i].u)))
                j++;
            if (j - i == 1)
                bd[nb++] = sd[i];
            i = j;
        }
        if (nb < 6) /* an outline and a hole need >= 3 sides each */
            continue;
        qsort(bd, (size_t)nb, sizeof *bd, cmp_dside_from);
        memset(used, 0, (size_t)nb);
        int64_t nl = 0, nv = 0;
        loop_off[0] = 0;
        for (int64_t e = 0; e < nb; e++) {
            if (used[e])
                continue;
            int64_t start = bd[e].u, cur = e;
            int closed = 0;
            while (!used[cur]) {
                used[cur] = 1;
                loop[nv++] = bd[cur].u;
                if (bd[cur].v == start) {
                    closed = 1;
                    break;
                }
                /* the first unused side leaving the end vertex */
                int64_t lo = 0, hi = nb, w = bd[cur].v;
                while (lo < hi) {
                    int64_t mid = lo + (hi - lo) / 2;
                    if (bd[mid].u < w)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                while (lo < nb && bd[lo].u == w && used[lo])
                    lo++;
                if (lo == nb || bd[lo].u != w)
                    break;
                cur = lo;
            }
            if (!closed) { /* not a simple loop: leave this sheet alone */
                nl = 0;
                break;
            }
            loop_off[++nl] = nv;
        }
        if (nl < 2)
            continue;
        /* the outline: the loop of the largest box */
        double best = -1;
        int64_t outline = -1;
        double *diag = malloc((size_t)nl * sizeof *diag);
        if (!diag) {
            st = MFG_ERR_NOMEM;
            break;
        }
        for (int64_t l = 0; l < nl; l++) {
            double lo3[3] = {INFINITY, INFINITY, INFINITY}, hi3[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int64_t i = loop_off[l]; i < loop_off[l + 1]; i++)
                for (int k = 0; k < 3; k++) {
                    lo3[k] = fmin(lo3[k], V[3 * loop[i] + k]);
                    hi3[k] = fmax(hi3[k], V[3 * loop[i] + k]);
                }
            double d = mfg_dist3(lo3, hi3);
            if (d > best) {
                best = d;
                outline = l;
            }
            /* width: the bounding box, or for a sliver 2 area / perimeter (its
             * inradius when a triangle) */
            double nw[3] = {0, 0, 0}, per = 0;
            for (int64_t i = loop_off[l]; i < loop_off[l + 1]; i++) {
                int64_t j = i + 1 < loop_off[l + 1] ? i + 1 : loop_off[l];
                double c[3];
                mfg_cross3(V + 3 * loop[i], V + 3 * loop[j], c);
                for (int k = 0; k < 3; k++)
                    nw[k] += c[k];
                per += mfg_dist3(V + 3 * loop[i], V + 3 * loop[j]);
            }
            diag[l] = per > 0 ? fmin(d, mfg_norm3(nw) / per) : d;
        }
        for (int64_t l = 0; l < nl && st == MFG_OK; l++) {
            int64_t a = loop_off[l], n = loop_off[l + 1] - a;
            if (l == outline || n < 3 || !(diag[l] <= 0.25 * tol))
                continue;
            for (int64_t i = 1; i + 1 < n; i++)
                if (!ibuf_push(&fill, r) || !ibuf_push(&fill, loop[a]) ||
                    !ibuf_push(&fill, loop[a + i + 1]) || !ibuf_push(&fill, loop[a + i]))
                    st = MFG_ERR_NOMEM;
        }
        free(diag);
    }
    if (st != MFG_OK || fill.n == 0)
        goto done;
    {
        int64_t nf = fill.n / 4, tot = m->sheet_triangle_offsets[m->nsheets];
        int64_t *T = malloc((size_t)(3 * (tot + nf) + 1) * sizeof *T);
        if (!T) {
            st = MFG_ERR_NOMEM;
            goto done;
        }
        int64_t w = 0, f = 0;
        for (int64_t r = 0; r < m->nsheets; r++) {
            int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
            memcpy(T + 3 * w, m->sheet_triangles + 3 * t0, (size_t)(3 * (t1 - t0)) * sizeof *T);
            m->sheet_triangle_offsets[r] = w;
            w += t1 - t0;
            for (; f < nf && fill.v[4 * f] == r; f++, w++)
                memcpy(T + 3 * w, fill.v + 4 * f + 1, 3 * sizeof *T);
        }
        m->sheet_triangle_offsets[m->nsheets] = w;
        free(m->sheet_triangles);
        m->sheet_triangles = T;
    }
done:
    free(sd);
    free(bd);
    free(used);
    free(loop);
    free(loop_off);
    free(fill.v);
    return st;
}

/* ---- needles ---------------------------------------------------------------------------------- */

/* The corner of triangle t (0 .. 2) within eps of its opposite side -- the longest --, or
 * -1.  A triangle with a repeated vertex counts (corner 0). */
static int needle_corner(const double *V, const int64_t *tv, double eps)
{
    if (tv[0] == tv[1] || tv[1] == tv[2] || tv[2] == tv[0])
        return 0;
    int j = 0;
    double best = -1;
    for (int c = 0; c < 3; c++) {
        double d = mfg_dist3(V + 3 * tv[(c + 1) % 3], V + 3 * tv[(c + 2) % 3]);
        if (d > best) {
            best = d;
            j = c;
        }
    }
    if (!(best > 0))
        return j;
    double u[3], w[3], n[3];
    mfg_sub3(V + 3 * tv[(j + 2) % 3], V + 3 * tv[(j + 1) % 3], u);
    mfg_sub3(V + 3 * tv[j], V + 3 * tv[(j + 1) % 3], w);
    mfg_cross3(u, w, n);
    return mfg_norm3(n) / best <= eps ? j : -1;
}

/* Is directed side (u, v) one of triangle tv's? */
static int has_side(const int64_t *tv, int64_t u, int64_t v)
{
    for (int c = 0; c < 3; c++)
        if (tv[c] == u && tv[(c + 1) % 3] == v)
            return 1;
    return 0;
}

/* Why: a sheet's triangles come from the leaves' cuts, the collapses and the pinhole fans;
 * where three of their vertices end on one straight seam run (full mode's collapses on the
 * cup, the pinhole fans between two nearly collinear rows, the outward 2 mm shell box's
 * strip), the triangle has no area: no normal, no thickness, a distance query divides by
 * zero on it and a FEM mesher refuses the face.  Dropping it alone would open a slit;
 * splitting the neighbour across its long side at the flat corner keeps the sheet closed
 * and its area (within eps times the side).  A needle on the sheet's boundary just goes:
 * the boundary then runs through the flat corner, the same line.  In place per sheet
 * (a split reuses both slots); sheets that lost triangles are compacted at the end. */
mfg_status md_drop_needles(mfg_medial *m, double eps)
{
    int64_t maxt = 0, tot = m->sheet_triangle_offsets[m->nsheets];
    for (int64_t r = 0; r < m->nsheets; r++)
        if (m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r] > maxt)
            maxt = m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r];
    char *dead = calloc((size_t)(tot + 1), 1);
    int64_t qcap = 5 * maxt + 32;
    int64_t *todo = malloc((size_t)qcap * sizeof *todo);
    hmap side = {0};
    mfg_status st = MFG_OK;
    int64_t ndead = 0;
    if (!dead || !todo) {
        st = MFG_ERR_NOMEM;
        goto done;
    }
    for (int64_t r = 0; r < m->nsheets && st == MFG_OK; r++) {
        int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
        const double *V = m->sheet_vertices + 3 * m->sheet_vertex_offsets[r];
        int64_t *T = m->sheet_triangles;
        int64_t nq = 0;
        for (int64_t t = t0; t < t1; t++)
            if (needle_corner(V, T + 3 * t, eps) >= 0)
                todo[nq++] = t;
        if (nq == 0)
            continue;
        /* directed side -> triangle; a stale entry is caught by has_side */
        hmap_free(&side);
        if (!hmap_init(&side, 3 * (t1 - t0))) {
            st = MFG_ERR_NOMEM;
            break;
        }
        for (int64_t t = t0; t < t1 && st == MFG_OK; t++)
            for (int c = 0; c < 3; c++) {
                hkey k = mkkey(T[3 * t + c], T[3 * t + (c + 1) % 3], 0, 0);
                if (!hmap_put(&side, &k, t))
                    st = MFG_ERR_NOMEM;
            }
        /* each split leaves two triangles to look at again; the guard stops a cycle
         * among coincident points (the queue, 5 times the triangles, outlasts it) */
        for (int64_t guard = 0; nq > 0 && st == MFG_OK && guard < 4 * (t1 - t0) + 16; guard++) {
            int64_t t = todo[--nq];
            if (dead[t])
                continue;
            int64_t *tv = T + 3 * t;
            int j = needle_corner(V, tv, eps);
            if (j < 0)
                continue;
            /* flat corner b on the side c -> a; the neighbour across runs a -> c */
            int64_t b = tv[j], c = tv[(j + 1) % 3], a = tv[(j + 2) % 3];
            hkey k = mkkey(a, c, 0, 0);
            int64_t n = hmap_get(&side, &k);
            if (b == c || c == a || a == b || n < t0 || n >= t1 || n == t || dead[n] ||
                !has_side(T + 3 * n, a, c)) {
                dead[t] = 1; /* a repeated vertex, or on the boundary: it just goes */
                ndead++;
                continue;
            }
            int64_t *g = T + 3 * n, o = -1;
            for (int q = 0; q < 3; q++)
                if (g[q] == a)
                    o = g[(q + 2) % 3];
            /* (a, b, o) in t's slot, (b, c, o) in n's: g's orientation, b on its side */
            int64_t nt[2][3] = {{a, b, o}, {b, c, o}}, slot[2] = {t, n};
            for (int s2 = 0; s2 < 2 && st == MFG_OK; s2++) {
                memcpy(T + 3 * slot[s2], nt[s2], sizeof nt[s2]);
                for (int q = 0; q < 3; q++) {
                    hkey e = mkkey(nt[s2][q], nt[s2][(q + 1) % 3], 0, 0);
                    if (!hmap_put(&side, &e, slot[s2]))
                        st = MFG_ERR_NOMEM;
                }
                if (nq < qcap)
                    todo[nq++] = slot[s2];
            }
        }
    }
    if (st != MFG_OK || ndead == 0)
        goto done;
    /* compact: the triangles, the vertices no triangle uses any more, and a sheet left
     * without triangles (one needle on its own) */
    {
        int64_t w = 0, wv = 0, ws = 0;
        for (int64_t r = 0; r < m->nsheets; r++) {
            int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
            int64_t v0 = m->sheet_vertex_offsets[r], v1 = m->sheet_vertex_offsets[r + 1];
            int64_t w0 = w;
            for (int64_t t = t0; t < t1; t++)
                if (!dead[t])
                    memmove(m->sheet_triangles + 3 * w++, m->sheet_triangles + 3 * t, 3 * sizeof(int64_t));
            if (w == w0)
                continue;
            /* the sheet's vertices that are still used, kept in order, renumbered */
            int64_t nvr = v1 - v0;
            int64_t *map = malloc((size_t)(nvr + 1) * sizeof *map);
            if (!map) { /* nothing is inconsistent yet for the caller: it frees m */
                st = MFG_ERR_NOMEM;
                goto done;
            }
            for (int64_t i = 0; i < nvr; i++)
                map[i] = -1;
            for (int64_t i = 3 * w0; i < 3 * w; i++)
                map[m->sheet_triangles[i]] = 0;
            int64_t kv = 0;
            for (int64_t i = 0; i < nvr; i++)
                if (map[i] == 0) {
                    map[i] = kv;
                    memmove(m->sheet_vertices + 3 * (wv + kv), m->sheet_vertices + 3 * (v0 + i), 3 * sizeof(double));
                    m->sheet_radii[wv + kv] = m->sheet_radii[v0 + i];
                    kv++;
                }
            for (int64_t i = 3 * w0; i < 3 * w; i++)
                m->sheet_triangles[i] = map[m->sheet_triangles[i]];
            free(map);
            m->sheet_elements[2 * ws] = m->sheet_elements[2 * r];
            m->sheet_elements[2 * ws + 1] = m->sheet_elements[2 * r + 1];
            m->sheet_forms[ws] = m->sheet_forms[r];
            m->sheet_vertex_offsets[ws] = wv;
            m->sheet_triangle_offsets[ws] = w0;
            wv += kv;
            ws++;
        }
        m->sheet_triangle_offsets[ws] = w;
        m->sheet_vertex_offsets[ws] = wv;
        m->nsheets = ws;
    }
done:
    hmap_free(&side);
    free(dead);
    free(todo);
    return st;
}

/* ---- sheets narrower than the tolerance -------------------------------------------------- */

/* (a, b, seam): the seams whose set holds a pair, for drop_narrow_sheets. */
typedef struct pair_seam {
    int64_t a, b, seam;
} pair_seam;

static int cmp_pair_seam(const void *pa, const void *pb)
{
    const pair_seam *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->seam > y->seam) - (x->seam < y->seam);
}

/* Is p within d of a seam of ps[lo .. hi)? */
static int near_seams(const seam_out *o, const pair_seam *ps, int64_t lo, int64_t hi,
                      const double *p, double d)
{
    for (int64_t k = lo; k < hi; k++) {
        int64_t i = ps[k].seam, p0 = o->pt_off.v[i], np = o->pt_off.v[i + 1] - p0;
        if (md_polyline_dist(o->pts.v + 3 * p0, np, p) <= d)
            return 1;
    }
    return 0;
}

/* Drops the sheets that lie within the tolerance of their own seams.  A bisector sheet
 * narrower than a leaf (on a tessellated wall, a facet against a reflex edge of the
 * facing wall: a strip in the edge's Voronoi wedge, 2 pi / n wide) is sampled by the
 * leaves only where it happens to cross them: a rotated 64-segment cup gave 3 592
 * one-triangle sheets, one strip in up to 33 pieces.  Its seams (traced, recover_junctions)
 * already carry it within the tolerance, so such pieces add nothing but clutter.  A sheet
 * goes when, for every triangle (sides at most NARROW_GRID tol / 2), the points of a
 * barycentric grid of spacing <= tol / 2 lie within tol / 2 of seams whose set holds the
 * sheet's pair: every point of it is then within tol / 2 + tol / (2 sqrt 3) < tol of
 * those seams, so the result stays complete within the tolerance. */
#define NARROW_GRID 16
mfg_status md_drop_narrow_sheets(const seam_out *o, double tol, mfg_medial *m)
{
    int64_t cnt = 0;
    for (int64_t i = 0; i < o->n; i++) {
        int64_t ne = o->el_off.v[i + 1] - o->el_off.v[i];
        cnt += ne * (ne - 1) / 2;
    }
    pair_seam *ps = malloc((size_t)(cnt + 1) * sizeof *ps);
    if (!ps)
        return MFG_ERR_NOMEM;
    int64_t k = 0;
    for (int64_t i = 0; i < o->n; i++) {
        const int64_t *e = o->elems.v + o->el_off.v[i];
        int64_t ne = o->el_off.v[i + 1] - o->el_off.v[i];
        for (int64_t a = 0; a < ne; a++)
            for (int64_t b = a + 1; b < ne; b++)
                ps[k++] = (pair_seam){e[a] < e[b] ? e[a] : e[b], e[a] < e[b] ? e[b] : e[a], i};
    }
    if (k > 1)
        qsort(ps, (size_t)k, sizeof *ps, cmp_pair_seam);
    int64_t w = 0, wv = 0, wt = 0;
    for (int64_t r = 0; r < m->nsheets; r++) {
        int64_t a = m->sheet_elements[2 * r], b = m->sheet_elements[2 * r + 1];
        int64_t v0 = m->sheet_vertex_offsets[r], v1 = m->sheet_vertex_offsets[r + 1];
        int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
        /* the run of seams holding (a, b) */
        int64_t lo = 0, hi = k;
        while (lo < hi) {
            int64_t mid = lo + (hi - lo) / 2;
            if (ps[mid].a < a || (ps[mid].a == a && ps[mid].b < b))
                lo = mid + 1;
            else
                hi = mid;
        }
        int64_t end = lo;
        while (end < k && ps[end].a == a && ps[end].b == b)
            end++;
        int narrow = end > lo;
        for (int64_t t = t0; t < t1 && narrow; t++) {
            const double *P[3];
            double longest = 0;
            for (int c = 0; c < 3; c++)
                P[c] = m->sheet_vertices + 3 * (v0 + m->sheet_triangles[3 * t + c]);
            for (int c = 0; c < 3; c++)
                longest = fmax(longest, mfg_dist3(P[c], P[(c + 1) % 3]));
            /* the barycentric grid of step 1/g: every point of the triangle lies within
             * longest / (g sqrt 3) <= tol / (2 sqrt 3) of a grid point */
            double g = ceil(longest / (0.5 * tol));
            if (!(g <= NARROW_GRID))
                narrow = 0;
            int gi = narrow ? (int)(g > 1 ? g : 1) : 0;
            for (int i = 0; i <= gi && narrow; i++)
                for (int j = 0; i + j <= gi && narrow; j++) {
                    double u = (double)i / gi, v = (double)j / gi, q[3];
                    for (int x = 0; x < 3; x++)
                        q[x] = P[0][x] + u * (P[1][x] - P[0][x]) + v * (P[2][x] - P[0][x]);
                    narrow = near_seams(o, ps, lo, end, q, 0.5 * tol);
                }
        }
        if (narrow)
            continue;
        /* keep: compact in place */
        memmove(m->sheet_vertices + 3 * wv, m->sheet_vertices + 3 * v0, (size_t)(3 * (v1 - v0)) * sizeof(double));
        memmove(m->sheet_radii + wv, m->sheet_radii + v0, (size_t)(v1 - v0) * sizeof(double));
        memmove(m->sheet_triangles + 3 * wt, m->sheet_triangles + 3 * t0, (size_t)(3 * (t1 - t0)) * sizeof(int64_t));
        m->sheet_elements[2 * w] = a;
        m->sheet_elements[2 * w + 1] = b;
        m->sheet_forms[w] = m->sheet_forms[r];
        m->sheet_vertex_offsets[w] = wv;
        m->sheet_triangle_offsets[w] = wt;
        wv += v1 - v0;
        wt += t1 - t0;
        w++;
    }
    m->sheet_vertex_offsets[w] = wv;
    m->sheet_triangle_offsets[w] = wt;
    m->nsheets = w;
    free(ps);
    return MFG_OK;
}
