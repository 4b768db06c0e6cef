/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* planar_merge.c - the pieces of one plane merged back into one triangulated region.
 *
 * A region (triangles of one group joined through shared edges) is bounded by the
 * directed edges whose twin is not in it.  Its boundary loops are followed round every
 * vertex through the region's own triangles (the edge after a boundary edge is the next
 * boundary edge of the fan of region triangles at its head), so a region touching itself
 * at a vertex keeps its corners apart.  The loops, projected onto the coordinate plane
 * closest to the region's plane, are triangulated again on their own vertices
 * (polygon_triangulate.c), and the result is checked before it replaces the region: the
 * same boundary edges, every new edge new to the mesh, every triangle counter-clockwise,
 * the same area.
 */
#include "mesh/planar_merge.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/hashmap.h"
#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "mesh/polygon_triangulate.h"
#include "common/predicates.h"

/* How far the corners of a region may lie from one plane, relative to their coordinates:
 * rounding of the lifts (cos, sin, a few products) is some 1e-16; more is a corner that is
 * not on the plane. */
#define PM_FLAT 1e-12
/* The new triangulation of a region keeps its area to this relative error (the sums of
 * a few hundred cross products round to ~1e-14 of the area); more is a wrong one. */
#define PM_AREA_REL 1e-9

/* Directed edges (a, b) -> an int64 value, on the library's shared map (hashmap.h). */
static int64_t edges_get(const hmap *m, int64_t a, int64_t b)
{
    hkey k = mkkey(a, b, 0, 0);
    return hmap_get(m, &k);
}

/* sets (a, b) -> v (v >= 0) unless (a, b) is there already: 1 set, 0 there already (the
 * value is kept), -1 out of memory */
static int edges_put(hmap *m, int64_t a, int64_t b, int64_t v)
{
    hkey k = mkkey(a, b, 0, 0);
    if (hmap_get(m, &k) >= 0)
        return 0;
    return hmap_put(m, &k, v) ? 1 : -1;
}

typedef struct pm_item {
    int64_t comp, tri;
} pm_item;

static int cmp_item(const void *pa, const void *pb)
{
    const pm_item *a = pa, *b = pb;
    if (a->comp != b->comp)
        return a->comp < b->comp ? -1 : 1;
    return (a->tri > b->tri) - (a->tri < b->tri);
}

typedef struct pm_pair {
    int64_t a, b;
} pm_pair;

static int cmp_pair(const void *pa, const void *pb)
{
    const pm_pair *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

static int has_pair(const pm_pair *s, int64_t n, int64_t a, int64_t b)
{
    pm_pair k = {a, b};
    return bsearch(&k, s, (size_t)n, sizeof *s, cmp_pair) != NULL;
}

typedef struct pm_seg {
    double x0, x1, y0, y1; /* bounding box */
    int64_t p, q;          /* points */
} pm_seg;

static int cmp_seg(const void *pa, const void *pb)
{
    const pm_seg *a = pa, *b = pb;
    if (a->x0 != b->x0)
        return a->x0 < b->x0 ? -1 : 1;
    return (a->p > b->p) - (a->p < b->p);
}

static int pm_on_segment(const double *a, const double *b, const double *q)
{
    return mfg_orient2d(a[0], a[1], b[0], b[1], q[0], q[1]) == 0 && fmin(a[0], b[0]) <= q[0] &&
           q[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= q[1] && q[1] <= fmax(a[1], b[1]);
}

/* Do two loop edges meet other than at a common end point, or lie along each other? */
static int edges_clash(const double *xy, const pm_seg *e, const pm_seg *f)
{
    const double *p = xy + 2 * e->p, *q = xy + 2 * e->q, *r = xy + 2 * f->p, *s = xy + 2 * f->q;
#define PM_SAME(a, b) ((a)[0] == (b)[0] && (a)[1] == (b)[1])
    int pr = PM_SAME(p, r), ps = PM_SAME(p, s), qr = PM_SAME(q, r), qs = PM_SAME(q, s);
#undef PM_SAME
    if (pr + ps + qr + qs >= 2)
        return 1; /* the same edge twice */
    if (pr + ps + qr + qs == 1) {
        const double *x = pr || ps ? p : q, *a = pr || ps ? q : p, *b = pr || qr ? s : r;
        return mfg_orient2d(x[0], x[1], a[0], a[1], b[0], b[1]) == 0 &&
               mfg_dot2d(x[0], x[1], a[0], a[1], b[0], b[1]) > 0;
    }
    int o1 = mfg_orient2d(p[0], p[1], q[0], q[1], r[0], r[1]), o2 = mfg_orient2d(p[0], p[1], q[0], q[1], s[0], s[1]);
    int o3 = mfg_orient2d(r[0], r[1], s[0], s[1], p[0], p[1]), o4 = mfg_orient2d(r[0], r[1], s[0], s[1], q[0], q[1]);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return 1;
    return pm_on_segment(p, q, r) || pm_on_segment(p, q, s) || pm_on_segment(r, s, p) || pm_on_segment(r, s, q);
}

/* Are the loops simple: no edge of no length, no two edges meeting but at common end
 * points (a loop may touch itself or another at a vertex)?  The pieces of a face may be
 * folded over each other (slivers turned over in the plane); their boundary must not. */
static int loops_simple(const double *xy, const int64_t *lstart, int64_t nl, pm_seg *seg)
{
    int64_t n = 0;
    for (int64_t l = 0; l < nl; l++)
        for (int64_t i = lstart[l]; i < lstart[l + 1]; i++) {
            int64_t j = i + 1 < lstart[l + 1] ? i + 1 : lstart[l];
            const double *p = xy + 2 * i, *q = xy + 2 * j;
            if (p[0] == q[0] && p[1] == q[1])
                return 0;
            seg[n].p = i;
            seg[n].q = j;
            seg[n].x0 = fmin(p[0], q[0]);
            seg[n].x1 = fmax(p[0], q[0]);
            seg[n].y0 = fmin(p[1], q[1]);
            seg[n].y1 = fmax(p[1], q[1]);
            n++;
        }
    qsort(seg, (size_t)n, sizeof *seg, cmp_seg);
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = i + 1; j < n && seg[j].x0 <= seg[i].x1; j++)
            if (seg[j].y0 <= seg[i].y1 && seg[i].y0 <= seg[j].y1 && edges_clash(xy, &seg[i], &seg[j]))
                return 0;
    return 1;
}

/* Scratch of one region's work, grown as needed. */
typedef struct pm_work {
    int64_t *bnd;     /* boundary half-edges */
    int64_t *bnext;   /* per boundary edge: the next one on its loop */
    char *bseen;
    int64_t *lstart;  /* loops: offsets into the loop points */
    int64_t *lvert;   /* loop points: vertex ids */
    double *xy;       /* loop points projected */
    int64_t *ntri;    /* new triangles, as loop points */
    pm_pair *newe;    /* new directed edges */
    pm_pair *olde;    /* boundary directed edges */
    pm_seg *seg;      /* loop edges */
    int64_t *tvert;   /* thinning: the kept loop points' vertex ids, ... */
    double *txy;      /* ... and their projections */
    int64_t *tstart;  /* ... and the thinned loops' offsets */
    int64_t nl;       /* the loops of the region last triangulated */
    int64_t cap;
} pm_work;

static int work_grow(pm_work *w, int64_t n)
{
    if (n <= w->cap)
        return 1;
    int64_t c = mfg_grown_cap(w->cap, n, 64);
    int ok = 1; /* every array is tried: one grown before a failure is only larger */
    ok &= mfg_resize((void **)&w->bnd, c, sizeof *w->bnd);
    ok &= mfg_resize((void **)&w->bnext, c, sizeof *w->bnext);
    ok &= mfg_resize((void **)&w->bseen, c, 1);
    ok &= mfg_resize((void **)&w->lstart, c + 1, sizeof *w->lstart);
    ok &= mfg_resize((void **)&w->lvert, c, sizeof *w->lvert);
    ok &= mfg_resize((void **)&w->xy, 2 * c, sizeof *w->xy);
    ok &= mfg_resize((void **)&w->ntri, 3 * c, sizeof *w->ntri);
    ok &= mfg_resize((void **)&w->newe, 3 * c, sizeof *w->newe);
    ok &= mfg_resize((void **)&w->olde, c, sizeof *w->olde);
    ok &= mfg_resize((void **)&w->seg, c, sizeof *w->seg);
    ok &= mfg_resize((void **)&w->tvert, c, sizeof *w->tvert);
    ok &= mfg_resize((void **)&w->txy, 2 * c, sizeof *w->txy);
    ok &= mfg_resize((void **)&w->tstart, c + 1, sizeof *w->tstart);
    if (!ok)
        return 0;
    w->cap = c;
    return 1;
}

static void work_free(pm_work *w)
{
    free(w->bnd);
    free(w->bnext);
    free(w->bseen);
    free(w->lstart);
    free(w->lvert);
    free(w->xy);
    free(w->ntri);
    free(w->newe);
    free(w->olde);
    free(w->seg);
    free(w->tvert);
    free(w->txy);
    free(w->tstart);
}

/* Shared state of the pass. */
typedef struct pm_ctx {
    const double *xyz;
    const int64_t *tris;
    int64_t nt;
    const int64_t *comp;  /* per triangle: its region (a triangle index), -1 */
    hmap he;              /* (a, b) -> half-edge 3 t + k */
    hmap added;           /* new inner edges of regions already merged */
    int64_t *deg;         /* per vertex: triangles using it */
    int64_t *cnt, *stamp; /* per vertex: uses in the current region */
    char *onloop;         /* per vertex: on a loop of the current region */
    int64_t *bidx;        /* per half-edge: its index among the region's boundary edges */
    const int64_t *label; /* thinning (NULL: none): per vertex its chain, see the header */
    double thin_tol;
    int64_t *lstamp;      /* per vertex: the region stamp when it was seen on a loop, ... */
    int64_t *pinch;       /* ... and when it was seen twice */
    pm_work w;
} pm_ctx;

static double proj_area2(const double *p, const double *q, const double *r, int u, int v)
{
    return (q[u] - p[u]) * (r[v] - p[v]) - (q[v] - p[v]) * (r[u] - p[u]);
}

/* May loop vertex x of region stamp go with a chord, given the chain *lab of the run so
 * far (-1: none yet)?  Not a corner, a pinch, or a vertex a triangle outside uses. */
static int thin_may_drop(const pm_ctx *P, int64_t stampv, int64_t x, int64_t *lab)
{
    if (P->pinch[x] == stampv || P->cnt[x] != P->deg[x])
        return 0;
    int64_t l = P->label[x];
    if (l == -1)
        return 1;
    if (l < 0 || (*lab >= 0 && l != *lab))
        return 0;
    *lab = l;
    return 1;
}

/* One loop being thinned: its points L[i], i taken modulo m. */
typedef struct thin_loop {
    const pm_ctx *P;
    int64_t stampv;
    const int64_t *L;
    int64_t m;
} thin_loop;

/* Do the points strictly between a and j (a < j <= a + m) all go with the chord from
 * L[a] to L[j]? */
static int thin_chord_holds(const void *ctx, int64_t a, int64_t j)
{
    const thin_loop *tl = ctx;
    const pm_ctx *P = tl->P;
    const int64_t *L = tl->L, m = tl->m, stampv = tl->stampv;
    const double *A = P->xyz + 3 * L[a % m], *B = P->xyz + 3 * L[j % m];
    double lim = P->thin_tol * P->thin_tol;
    int64_t lab = -1;
    for (int64_t q = a + 1; q < j; q++) {
        int64_t x = L[q % m];
        if (!thin_may_drop(P, stampv, x, &lab) || !(mfg_seg_dist2(P->xyz + 3 * x, A, B) <= lim))
            return 0;
    }
    return 1;
}

/* Thins the loops w->lstart / lvert / xy (nl loops, np points) into tstart / tvert / txy:
 * from a kept point (a vertex that must stay, else the loop's first), each chord reaches
 * the farthest point it holds for (mfg_farthest_chord: O(n log n) on a straight run, as
 * the seams' thinning).  Returns the points dropped, or -1 when a loop would keep fewer
 * than 3 (then nothing is thinned). */
static int64_t thin_loops(pm_ctx *P, int64_t stampv, int64_t nl, int64_t np)
{
    pm_work *w = &P->w;
    int64_t out = 0;
    for (int64_t l = 0; l < nl; l++) {
        const int64_t *L = w->lvert + w->lstart[l];
        const double *XY = w->xy + 2 * w->lstart[l];
        int64_t m = w->lstart[l + 1] - w->lstart[l], anchor = 0, lab;
        thin_loop tl = {P, stampv, L, m};
        for (int64_t i = 0; i < m; i++) {
            lab = -1;
            if (!thin_may_drop(P, stampv, L[i], &lab) || P->label[L[i]] < -1) {
                anchor = i;
                break;
            }
        }
        w->tstart[l] = out;
        int64_t kept = 0;
        for (int64_t a = anchor; a < anchor + m;) {
            w->tvert[out] = L[a % m];
            w->txy[2 * out] = XY[2 * (a % m)];
            w->txy[2 * out + 1] = XY[2 * (a % m) + 1];
            out++;
            kept++;
            a = mfg_farthest_chord(a, anchor + m, thin_chord_holds, &tl);
        }
        if (kept < 3)
            return -1;
    }
    w->tstart[nl] = out;
    return np - out;
}

/* The region of the n triangles its[0..n): triangulated again into w.ntri (as vertex ids,
 * *nnew of them) when that is safe and gains; 1 when done, 0 when left, -1 out of memory. */
static int merge_region(pm_ctx *P, const pm_item *its, int64_t n, int64_t *nnew)
{
    pm_work *w = &P->w;
    const int64_t C = its[0].comp;
    const int64_t stampv = C + 1;
    /* the plane's normal (sum of the triangles' normals) and the projection */
    double N[3] = {0, 0, 0};
    for (int64_t i = 0; i < n; i++) {
        const int64_t *t = P->tris + 3 * its[i].tri;
        const double *a = P->xyz + 3 * t[0], *b = P->xyz + 3 * t[1], *c = P->xyz + 3 * t[2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        N[0] += e1[1] * e2[2] - e1[2] * e2[1];
        N[1] += e1[2] * e2[0] - e1[0] * e2[2];
        N[2] += e1[0] * e2[1] - e1[1] * e2[0];
    }
    int k = fabs(N[0]) >= fabs(N[1]) ? (fabs(N[0]) >= fabs(N[2]) ? 0 : 2) : (fabs(N[1]) >= fabs(N[2]) ? 1 : 2);
    if (!(fabs(N[k]) > 0))
        return 0;
    /* (u, v) turns like the plane seen from the side N points to */
    int u = (k + 1) % 3, v = (k + 2) % 3;
    if (N[k] < 0) {
        int s = u;
        u = v;
        v = s;
    }
    /* the area (of pieces folded over each other too: they cancel) */
    double area_old = 0;
    int64_t nb = 0;
    for (int64_t i = 0; i < n; i++) {
        int64_t t = its[i].tri;
        const int64_t *tv = P->tris + 3 * t;
        const double *a = P->xyz + 3 * tv[0], *b = P->xyz + 3 * tv[1], *c = P->xyz + 3 * tv[2];
        area_old += proj_area2(a, b, c, u, v);
        for (int q = 0; q < 3; q++) {
            int64_t x = tv[q], y = tv[(q + 1) % 3];
            if (P->stamp[x] != stampv) {
                P->stamp[x] = stampv;
                P->cnt[x] = 0;
                P->onloop[x] = 0;
            }
            P->cnt[x]++;
            int64_t tw = edges_get(&P->he, y, x);
            if (tw < 0 || P->comp[tw / 3] != C) {
                if (!work_grow(w, nb + 1))
                    return -1;
                P->bidx[3 * t + q] = nb;
                w->bnd[nb++] = 3 * t + q;
            }
        }
    }
    if (nb < 3)
        return 0;
    /* inner vertices: used by no triangle outside the region; without one nothing is gained
     * (a triangulation on the same vertices has as many triangles) */
    for (int64_t j = 0; j < nb; j++) {
        int64_t h = w->bnd[j];
        P->onloop[P->tris[h]] = 1;
    }
    int64_t ninner = 0;
    for (int64_t i = 0; i < n; i++) {
        const int64_t *tv = P->tris + 3 * its[i].tri;
        for (int q = 0; q < 3; q++) {
            int64_t x = tv[q];
            if (P->onloop[x])
                continue;
            if (P->cnt[x] != P->deg[x])
                return 0;
            ninner++;
        }
    }
    if (ninner == 0 && !P->label)
        return 0;
    /* one plane up to rounding: a corner off it (the sweep's lifts near a tangent root,
     * where acos loses half the digits, lie some 1e-8 off) would tilt the long triangles
     * of the new triangulation, and the surface would move by that much */
    {
        double nn = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]), scale = 0, lo = INFINITY, hi = -INFINITY;
        const double *o = P->xyz + 3 * P->tris[3 * its[0].tri];
        for (int64_t i = 0; i < n; i++)
            for (int q = 0; q < 3; q++) {
                const double *p = P->xyz + 3 * P->tris[3 * its[i].tri + q];
                double d = ((p[0] - o[0]) * N[0] + (p[1] - o[1]) * N[1] + (p[2] - o[2]) * N[2]) / nn;
                lo = fmin(lo, d);
                hi = fmax(hi, d);
                scale = fmax(scale, fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2]))));
            }
        if (!(hi - lo <= PM_FLAT * scale))
            return 0;
    }
    /* the next boundary edge after each: round its head through the region's triangles */
    for (int64_t j = 0; j < nb; j++) {
        int64_t h = w->bnd[j];
        int64_t e = 3 * (h / 3) + (h % 3 + 1) % 3; /* head -> third corner */
        int64_t steps = 0;
        for (;;) {
            int64_t x = P->tris[e], y = P->tris[3 * (e / 3) + (e % 3 + 1) % 3];
            int64_t tw = edges_get(&P->he, y, x);
            if (tw < 0 || P->comp[tw / 3] != C)
                break;
            e = 3 * (tw / 3) + (tw % 3 + 1) % 3;
            if (++steps > n)
                return 0;
        }
        w->bnext[j] = P->bidx[e];
        w->bseen[j] = 0;
    }
    /* the loops: every boundary edge on exactly one */
    int64_t nl = 0, np = 0;
    for (int64_t j = 0; j < nb; j++) {
        if (w->bseen[j])
            continue;
        w->lstart[nl++] = np;
        int64_t e = j;
        do {
            if (w->bseen[e] || np >= nb)
                return 0;
            w->bseen[e] = 1;
            int64_t x = P->tris[w->bnd[e]];
            if (P->label) {
                if (P->lstamp[x] == stampv)
                    P->pinch[x] = stampv;
                P->lstamp[x] = stampv;
            }
            const double *p = P->xyz + 3 * x;
            w->lvert[np] = x;
            w->xy[2 * np] = p[u];
            w->xy[2 * np + 1] = p[v];
            np++;
            e = w->bnext[e];
        } while (e != j);
    }
    w->lstart[nl] = np;
    if (!work_grow(w, np + 2 * nl + 2))
        return -1;
    if (P->label) {
        /* the thinned loops take the loops' place (their arrays swap) */
        int64_t dropped = thin_loops(P, stampv, nl, np);
        if (dropped < 0 || (dropped == 0 && ninner == 0))
            return 0;
        if (dropped > 0) {
            int64_t *ti = w->lvert;
            w->lvert = w->tvert;
            w->tvert = ti;
            ti = w->lstart;
            w->lstart = w->tstart;
            w->tstart = ti;
            double *td = w->xy;
            w->xy = w->txy;
            w->txy = td;
            np -= dropped;
            /* the loops' area (shoelace, doubled as proj_area2), the old area's stand-in */
            area_old = 0;
            for (int64_t l = 0; l < nl; l++)
                for (int64_t i = w->lstart[l]; i < w->lstart[l + 1]; i++) {
                    int64_t j = i + 1 < w->lstart[l + 1] ? i + 1 : w->lstart[l];
                    area_old += w->xy[2 * i] * w->xy[2 * j + 1] - w->xy[2 * j] * w->xy[2 * i + 1];
                }
        }
    }
    if (!loops_simple(w->xy, w->lstart, nl, w->seg))
        return 0;
    int64_t nt = 0;
    w->nl = nl;
    int rc = mfg_polygon_triangulate(w->xy, w->lstart, nl, w->ntri, &nt);
    if (rc <= 0)
        return rc;
    if (nt >= n)
        return 0;
    /* the check: strictly counter-clockwise triangles, the same boundary edges, every
     * other edge twice in opposite directions and new to the mesh, the same area */
    double area_new = 0;
    for (int64_t i = 0; i < nt; i++) {
        int64_t *t = w->ntri + 3 * i;
        for (int q = 0; q < 3; q++)
            t[q] = w->lvert[t[q]];
        const double *a = P->xyz + 3 * t[0], *b = P->xyz + 3 * t[1], *c = P->xyz + 3 * t[2];
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] ||
            mfg_orient2d(a[u], a[v], b[u], b[v], c[u], c[v]) <= 0)
            return 0;
        area_new += proj_area2(a, b, c, u, v);
        for (int q = 0; q < 3; q++) {
            w->newe[3 * i + q].a = t[q];
            w->newe[3 * i + q].b = t[(q + 1) % 3];
        }
    }
    if (!(fabs(area_new - area_old) <= PM_AREA_REL * fabs(area_old)))
        return 0;
    /* the boundary: the loops' edges (the old boundary edges when nothing was thinned) */
    nb = np;
    for (int64_t l = 0; l < nl; l++)
        for (int64_t i = w->lstart[l]; i < w->lstart[l + 1]; i++) {
            int64_t j = i + 1 < w->lstart[l + 1] ? i + 1 : w->lstart[l];
            w->olde[i].a = w->lvert[i];
            w->olde[i].b = w->lvert[j];
        }
    qsort(w->olde, (size_t)nb, sizeof *w->olde, cmp_pair);
    qsort(w->newe, (size_t)(3 * nt), sizeof *w->newe, cmp_pair);
    for (int64_t j = 0; j + 1 < nb; j++)
        if (w->olde[j].a == w->olde[j + 1].a && w->olde[j].b == w->olde[j + 1].b)
            return 0;
    int64_t nbound = 0;
    for (int64_t i = 0; i < 3 * nt; i++) {
        const pm_pair *e = &w->newe[i];
        if (i + 1 < 3 * nt && e->a == e[1].a && e->b == e[1].b)
            return 0; /* an edge twice in one direction */
        if (has_pair(w->olde, nb, e->a, e->b)) {
            nbound++;
            continue;
        }
        if (!has_pair(w->newe, 3 * nt, e->b, e->a))
            return 0;
        /* an inner edge: not an edge of the mesh outside the region, nor new elsewhere */
        int64_t h1 = edges_get(&P->he, e->a, e->b), h2 = edges_get(&P->he, e->b, e->a);
        if ((h1 >= 0 && P->comp[h1 / 3] != C) || (h2 >= 0 && P->comp[h2 / 3] != C))
            return 0;
        if (edges_get(&P->added, e->a, e->b) >= 0 || edges_get(&P->added, e->b, e->a) >= 0)
            return 0;
    }
    if (nbound != nb)
        return 0;
    for (int64_t i = 0; i < 3 * nt; i++) {
        const pm_pair *e = &w->newe[i];
        if (!has_pair(w->olde, nb, e->a, e->b) && edges_put(&P->added, e->a, e->b, C) < 0)
            return -1;
    }
    *nnew = nt;
    return 1;
}

int mfg_merge_planar_groups(const double *xyz, int64_t nvertices, int64_t *tris, int64_t *ntris,
                            const int64_t *group, int64_t *nregions)
{
    return mfg_merge_planar_groups_thin(xyz, nvertices, tris, ntris, group, nregions, NULL, 0.0,
                                        NULL);
}

int mfg_merge_planar_groups_thin(const double *xyz, int64_t nvertices, int64_t *tris,
                                 int64_t *ntris, const int64_t *group, int64_t *nregions,
                                 const int64_t *label, double thin_tol, char *thinned)
{
    int64_t nt = *ntris;
    if (nregions)
        *nregions = 0;
    pm_ctx P;
    memset(&P, 0, sizeof P);
    P.xyz = xyz;
    P.tris = tris;
    P.nt = nt;
    int64_t *comp = malloc((size_t)(nt + 1) * sizeof *comp);
    int64_t *parent = malloc((size_t)(nt + 1) * sizeof *parent);
    pm_item *items = malloc((size_t)(nt + 1) * sizeof *items);
    char *dead = calloc((size_t)(nt + 1), 1);
    int64_t *out = malloc((size_t)(3 * nt + 1) * sizeof *out);
    P.deg = calloc((size_t)(nvertices + 1), sizeof *P.deg);
    P.cnt = malloc((size_t)(nvertices + 1) * sizeof *P.cnt);
    P.stamp = calloc((size_t)(nvertices + 1), sizeof *P.stamp);
    P.onloop = calloc((size_t)(nvertices + 1), 1);
    P.bidx = malloc((size_t)(3 * nt + 1) * sizeof *P.bidx);
    P.label = label;
    P.thin_tol = thin_tol;
    if (label) {
        P.lstamp = calloc((size_t)(nvertices + 1), sizeof *P.lstamp);
        P.pinch = calloc((size_t)(nvertices + 1), sizeof *P.pinch);
    }
    int ok = comp && parent && items && dead && out && P.deg && P.cnt && P.stamp && P.onloop && P.bidx &&
             (!label || (P.lstamp && P.pinch)) &&
             hmap_init(&P.he, 3 * nt) && hmap_init(&P.added, 64); /* added grows as regions merge */
    P.comp = comp;
    int manifold = 1;
    if (thinned)
        memset(thinned, 0, (size_t)nvertices);
    /* half-edges; a mesh with an edge twice in one direction is left alone */
    for (int64_t t = 0; t < nt && ok && manifold; t++)
        for (int q = 0; q < 3; q++) {
            int put = edges_put(&P.he, tris[3 * t + q], tris[3 * t + (q + 1) % 3], 3 * t + q);
            if (put < 0)
                ok = 0;
            else if (put == 0)
                manifold = 0;
            P.deg[tris[3 * t + q]]++;
        }
    int64_t nitems = 0, nout = 0;
    if (ok && manifold) {
        /* regions: triangles of one group joined through edges */
        for (int64_t t = 0; t < nt; t++)
            parent[t] = t;
        for (int64_t t = 0; t < nt; t++) {
            if (group[t] < 0)
                continue;
            for (int q = 0; q < 3; q++) {
                int64_t tw = edges_get(&P.he, tris[3 * t + (q + 1) % 3], tris[3 * t + q]);
                if (tw >= 0 && group[tw / 3] == group[t])
                    mfg_uf_union(parent, t, tw / 3);
            }
        }
        for (int64_t t = 0; t < nt; t++) {
            comp[t] = group[t] < 0 ? -1 : mfg_uf_find(parent, t);
            if (comp[t] >= 0) {
                items[nitems].comp = comp[t];
                items[nitems].tri = t;
                nitems++;
            }
        }
        qsort(items, (size_t)nitems, sizeof *items, cmp_item);
        /* new triangles go to the end of out; kept ones are copied first, below */
        int64_t *fresh = malloc((size_t)(3 * nt + 1) * sizeof *fresh);
        int64_t nfresh = 0;
        if (!fresh)
            ok = 0;
        for (int64_t i = 0; i < nitems && ok;) {
            int64_t j = i;
            while (j < nitems && items[j].comp == items[i].comp)
                j++;
            int64_t nnew = 0;
            int rc = j - i >= 3 ? merge_region(&P, items + i, j - i, &nnew) : 0;
            if (rc < 0) {
                ok = 0;
            } else if (rc > 0) {
                if (thinned)
                    for (int64_t q = 0; q < P.w.lstart[P.w.nl]; q++)
                        thinned[P.w.lvert[q]] = 1;
                memcpy(fresh + 3 * nfresh, P.w.ntri, (size_t)(3 * nnew) * sizeof *fresh);
                nfresh += nnew;
                for (int64_t q = i; q < j; q++)
                    dead[items[q].tri] = 1;
                if (nregions)
                    (*nregions)++;
            }
            i = j;
        }
        if (ok) {
            for (int64_t t = 0; t < nt; t++)
                if (!dead[t]) {
                    memcpy(out + 3 * nout, tris + 3 * t, 3 * sizeof *out);
                    nout++;
                }
            memcpy(out + 3 * nout, fresh, (size_t)(3 * nfresh) * sizeof *out);
            nout += nfresh;
        }
        free(fresh);
    }
    if (ok && manifold) {
        memcpy(tris, out, (size_t)(3 * nout) * sizeof *tris);
        *ntris = nout;
    }
    if (!ok && nregions)
        *nregions = 0;
    free(comp);
    free(parent);
    free(items);
    free(dead);
    free(out);
    free(P.deg);
    free(P.cnt);
    free(P.stamp);
    free(P.onloop);
    free(P.bidx);
    free(P.lstamp);
    free(P.pinch);
    hmap_free(&P.he);
    hmap_free(&P.added);
    work_free(&P.w);
    return ok;
}
