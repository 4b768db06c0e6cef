/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/points.c - The arrangement's point table: explicit vertices, implicit points
 * made once per construction, and the exact merge of equal positions. */
#include "arrange/arrange.h"

int arr_table_init(arr_table *T, const double *xyz, int64_t nv)
{
    memset(T, 0, sizeof *T);
    T->capxyz = nv + 64;
    T->cappts = 2 * nv + 64;
    T->xyz = malloc((size_t)T->capxyz * 3 * sizeof *T->xyz);
    T->pts = malloc((size_t)T->cappts * sizeof *T->pts);
    T->xc = arr_exact_cache_new();
    if (!T->xyz || !T->pts || !T->xc || !hmap_init(&T->keys, nv + 64)) {
        free(T->xyz);
        free(T->pts);
        arr_exact_cache_free(T->xc);
        memset(T, 0, sizeof *T);
        return 0;
    }
    memcpy(T->xyz, xyz, (size_t)nv * 3 * sizeof *xyz);
    T->nxyz = nv;
    for (int64_t i = 0; i < nv; i++) {
        arr_point *p = &T->pts[i];
        memset(p, 0, sizeof *p);
        p->kind = ARR_EXPLICIT;
        p->v[0] = i;
        arr_point_prepare(T->xyz, p);
    }
    T->npts = nv;
    return 1;
}

void arr_table_free(arr_table *T)
{
    free(T->xyz);
    free(T->pts);
    free(T->canon);
    arr_exact_cache_free(T->xc);
    hmap_free(&T->keys);
    memset(T, 0, sizeof *T);
}

/* Room for one more point; 0 when out of memory. */
static int grow_pts(arr_table *T)
{
    if (T->npts < T->cappts)
        return 1;
    int64_t cap = mfg_grown_cap(T->cappts, T->npts + 1, 16);
    arr_point *np = realloc(T->pts, (size_t)cap * sizeof *np);
    if (!np)
        return 0;
    mfg_huge_pages(np, (size_t)cap * sizeof *np);
    T->pts = np;
    T->cappts = cap;
    return 1;
}

/* Appends p (prepared here); its id, -1 when out of memory, -2 when p has no position
 * (or is off the grid: a lifted point's coordinates). */
static int64_t append(arr_table *T, arr_point *p)
{
    if (!arr_point_prepare(T->xyz, p))
        return -2;
    if (!grow_pts(T))
        return -1;
    T->pts[T->npts] = *p;
    return T->npts++;
}

/* The point with key k, made by p when it is new. */
/* 1 when point id holds the construction p (a key may outlive its point: arr_truncate
 * drops points, not keys, and a later point may take the id). */
static int same_construction(const arr_table *T, int64_t id, const arr_point *p)
{
    if (id >= T->npts)
        return 0;
    const arr_point *q = &T->pts[id];
    return q->kind == p->kind && q->axis == p->axis && !memcmp(q->v, p->v, sizeof q->v);
}

static int64_t keyed(arr_table *T, hkey k, arr_point *p)
{
    int64_t id = hmap_get(&T->keys, &k);
    if (id >= 0 && same_construction(T, id, p))
        return id;
    id = append(T, p);
    if (id < 0)
        return -1; /* a keyed construction the caller knows to exist: only memory fails */
    if (!hmap_put(&T->keys, &k, id))
        return -1;
    return id;
}

int64_t arr_lpi(arr_table *T, int64_t a, int64_t b, int64_t plane_id, const int64_t plane[3])
{
    if (a > b) {
        int64_t t = a;
        a = b;
        b = t;
    }
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = ARR_LPI;
    p.v[0] = a;
    p.v[1] = b;
    p.v[2] = plane[0];
    p.v[3] = plane[1];
    p.v[4] = plane[2];
    return keyed(T, mkkey(ARR_KEY_LPI, a, b, plane_id), &p);
}

int64_t arr_tpi(arr_table *T, const int64_t id[3], const int64_t plane[3][3])
{
    /* sorted by plane id so that the three orders give one key and one construction */
    int o[3] = {0, 1, 2};
    for (int i = 0; i < 2; i++)
        for (int j = i + 1; j < 3; j++)
            if (id[o[j]] < id[o[i]]) {
                int t = o[i];
                o[i] = o[j];
                o[j] = t;
            }
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = ARR_TPI;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            p.v[3 * i + k] = plane[o[i]][k];
    return keyed(T, mkkey(ARR_KEY_TPI, id[o[0]], id[o[1]], id[o[2]]), &p);
}

int64_t arr_ssi(arr_table *T, int64_t a, int64_t b, int64_t c, int64_t d, int axis)
{
    /* made once per crossing of one cluster (its member edges are merged first), so no
     * key: equal positions are merged by arr_dedupe */
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = ARR_SSI;
    p.axis = (uint8_t)axis;
    p.v[0] = a;
    p.v[1] = b;
    p.v[2] = c;
    p.v[3] = d;
    return append(T, &p);
}

int64_t arr_aux_vertex(arr_table *T, const double x[3])
{
    if (T->nxyz >= T->capxyz) {
        int64_t cap = mfg_grown_cap(T->capxyz, T->nxyz + 1, 16);
        double *nx = realloc(T->xyz, (size_t)cap * 3 * sizeof *nx);
        if (!nx)
            return -1;
        T->xyz = nx;
        T->capxyz = cap;
    }
    memcpy(T->xyz + 3 * T->nxyz, x, 3 * sizeof *x);
    return T->nxyz++;
}

int64_t arr_aux_point(arr_table *T, int64_t xi)
{
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = ARR_EXPLICIT;
    p.v[0] = xi;
    return append(T, &p);
}

int64_t arr_lift(arr_table *T, const int64_t tri[3], int axis, double u, double v)
{
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = ARR_LIFT;
    p.axis = (uint8_t)axis;
    p.v[0] = tri[0];
    p.v[1] = tri[1];
    p.v[2] = tri[2];
    p.lift[0] = u;
    p.lift[1] = v;
    return append(T, &p);
}

/* Keys of the dropped points stay in the map; keyed() checks them (same_construction). */
void arr_truncate(arr_table *T, int64_t npts)
{
    if (npts < T->npts) {
        T->npts = npts;
        arr_exact_cache_drop(T->xc, npts);
    }
}

/* ---- Exact merge of equal positions ------------------------------------------------- */

/* Rounded positions of equal points differ by a few ulps (arr_coords: within 2 ulps of
 * the exact value, coordinates at most ARR_COORD_MAX, so within 2^-48): an implicit point
 * is entered in every cell of this size that its box of DD_BOX about its rounded position
 * touches (one, nearly always), so two equal points share a cell, and is compared exactly
 * only with the earlier positions met there.  Explicit points are equal exactly when their
 * coordinates are. */
#define DD_CELL 0x1p-36
#define DD_BOX 0x1p-44

typedef struct dd_grid {
    hmap cells;       /* cell -> its last entry */
    int64_t *entry;   /* 2 per entry: point, previous entry of its cell */
    int64_t n, cap;
} dd_grid;

static int dd_enter(dd_grid *g, hkey key, int64_t p)
{
    if (!mfg_grow((void **)&g->entry, &g->cap, 2 * (g->n + 1), sizeof *g->entry))
        return 0;
    int64_t prev = hmap_get(&g->cells, &key);
    g->entry[2 * g->n] = p;
    g->entry[2 * g->n + 1] = prev;
    if (!hmap_put(&g->cells, &key, g->n))
        return 0;
    g->n++;
    return 1;
}

/* The cells of the box about x (their count, keys in out[0..7]). */
static int dd_cells(const double x[3], double box, hkey out[8])
{
    int64_t lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = (int64_t)floor((x[k] - box) / DD_CELL);
        hi[k] = (int64_t)floor((x[k] + box) / DD_CELL);
    }
    int n = 0;
    for (int64_t a = lo[0]; a <= hi[0]; a++)
        for (int64_t b = lo[1]; b <= hi[1]; b++)
            for (int64_t c = lo[2]; c <= hi[2]; c++)
                out[n++] = mkkey(a, b, c, 0);
    return n;
}

int arr_dedupe(arr_table *T, mfg_prog *prog)
{
    int64_t n = T->npts;
    int64_t *canon = realloc(T->canon, (size_t)(n + 1) * sizeof *canon);
    if (!canon)
        return 0;
    T->canon = canon;
    dd_grid g;
    memset(&g, 0, sizeof g);
    hmap exact;
    memset(&exact, 0, sizeof exact);
    if (!hmap_init(&g.cells, n + 1) || !hmap_init(&exact, n + 1)) {
        hmap_free(&g.cells);
        return 0;
    }
    arr_points P = arr_view(T);
    int ok = 1;
    /* the points a call before this one merged keep their representatives: they are only
     * entered (the representatives) for the new points to meet, not compared again (the
     * second call of an arrangement compared every point again: 9 % of a 10k torus) */
    int64_t done = T->ncanon <= n ? T->ncanon : 0;
    for (int64_t i = 0; i < n && ok; i++) {
        if ((i & 4095) == 0 && prog && !mfg_prog_poll(prog, (double)i, (double)n)) {
            ok = -1;
            break;
        }
        if (i < done && canon[i] != i)
            continue;
        canon[i] = i;
        const arr_point *pt = &T->pts[i];
        double x[3];
        hkey cells[8];
        if (pt->kind == ARR_EXPLICIT) {
            const double *c = T->xyz + 3 * pt->v[0];
            int64_t bits[3];
            for (int k = 0; k < 3; k++) {
                double v = c[k] == 0 ? 0 : c[k]; /* -0 and +0 are one position */
                memcpy(&bits[k], &v, sizeof v);
            }
            hkey key = mkkey(bits[0], bits[1], bits[2], 0);
            int64_t j = hmap_get(&exact, &key);
            if (j >= 0) {
                canon[i] = j;
                continue;
            }
            ok = hmap_put(&exact, &key, i) && dd_enter(&g, dd_cells(c, 0, cells) ? cells[0] : cells[0], i);
            continue;
        }
        arr_coords(&P, i, x);
        int nc = dd_cells(x, DD_BOX, cells);
        for (int q = 0; q < nc && canon[i] == i && i >= done; q++)
            for (int64_t en = hmap_get(&g.cells, &cells[q]); en >= 0; en = g.entry[2 * en + 1]) {
                int64_t j = g.entry[2 * en];
                if (canon[j] == j && arr_same(&P, i, j)) {
                    canon[i] = j;
                    break;
                }
            }
        if (canon[i] == i)
            for (int q = 0; q < nc && ok; q++)
                ok = dd_enter(&g, cells[q], i);
    }
    hmap_free(&g.cells);
    hmap_free(&exact);
    free(g.entry);
    if (ok != 1)
        return ok;
    T->ncanon = n;
    return 1;
}
