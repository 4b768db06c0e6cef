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
    if (!T->xyz || !T->pts || !hmap_init(&T->keys, nv + 64)) {
        free(T->xyz);
        free(T->pts);
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
static int64_t keyed(arr_table *T, hkey k, arr_point *p)
{
    int64_t id = hmap_get(&T->keys, &k);
    if (id >= 0)
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

void arr_truncate(arr_table *T, int64_t npts)
{
    if (npts < T->npts)
        T->npts = npts;
}

/* ---- Exact merge of equal positions ------------------------------------------------- */

/* Rounded positions of equal points differ by a few ulps (arr_coords: within 2 ulps of
 * the exact value, coordinates at most ARR_COORD_MAX): equal points fall into the same
 * cell of this size or into neighbouring ones, and are then compared exactly. */
#define DD_CELL 0x1p-36

int arr_dedupe(arr_table *T, mfg_prog *prog)
{
    int64_t n = T->npts;
    int64_t *canon = realloc(T->canon, (size_t)(n + 1) * sizeof *canon);
    if (canon)
        T->canon = canon;
    int64_t *next = malloc((size_t)(n + 1) * sizeof *next);
    int64_t *cell = malloc((size_t)(n + 1) * 3 * sizeof *cell);
    hmap grid;
    if (!canon || !next || !cell || !hmap_init(&grid, n + 1)) {
        free(next);
        free(cell);
        return 0;
    }
    arr_points P = arr_view(T);
    for (int64_t i = 0; i < n; i++) {
        double x[3];
        arr_coords(&P, i, x);
        for (int k = 0; k < 3; k++)
            cell[3 * i + k] = (int64_t)floor(x[k] / DD_CELL);
        canon[i] = i;
        hkey key = mkkey(cell[3 * i], cell[3 * i + 1], cell[3 * i + 2], 0);
        int64_t s = hmap_slot(&grid, &key);
        next[i] = grid.vals[s]; /* -1 when the cell is new */
        if (!hmap_put(&grid, &key, i)) {
            free(next);
            free(cell);
            hmap_free(&grid);
            return 0;
        }
    }
    /* each point against the representatives of the positions met so far in its
     * neighbourhood (not against every point there: many constructions of one point -
     * strips meeting on the axis - would make that quadratic in their number) */
    for (int64_t i = 0; i < n; i++) {
        if ((i & 4095) == 0 && prog && !mfg_prog_poll(prog, (double)i, (double)n)) {
            free(next);
            free(cell);
            hmap_free(&grid);
            return -1;
        }
        for (int d = 0; d < 27 && canon[i] == i; d++) {
            hkey key = mkkey(cell[3 * i] + d % 3 - 1, cell[3 * i + 1] + d / 3 % 3 - 1,
                             cell[3 * i + 2] + d / 9 - 1, 0);
            for (int64_t j = hmap_get(&grid, &key); j >= 0; j = next[j]) {
                if (j >= i || canon[j] != j)
                    continue; /* only earlier points that represent their position */
                if (arr_same(&P, i, j)) {
                    canon[i] = j;
                    break;
                }
            }
        }
    }
    for (int64_t i = 0; i < n; i++)
        canon[i] = canon[canon[i]]; /* a representative is its own: one step */
    T->ncanon = n;
    free(next);
    free(cell);
    hmap_free(&grid);
    return 1;
}
