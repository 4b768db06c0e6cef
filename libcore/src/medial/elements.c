/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* elements.c - the boundary elements of a closed mesh for the medial surface (issue 9; Lee
 * & Lee, the medial surface of a polyhedron; docs/design/medial.md section 1): faces merged
 * from coplanar adjacent triangles, edges as chains of mesh edges between two faces,
 * vertices at the chains' ends.  Their distances, restricted to their Voronoi regions (the
 * paper's special bisectors, Fig. 3), and the brute-force touching set are in
 * element_distances.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"

/* A face corner at a vertex this close to 180 deg counts as >= 180 deg (design 1.7: the
 * vertex's region is then empty, the faces cover it).  [choice] the angle sum is in
 * floating point; a true 180 deg corner comes out within a few ulps of pi. */
#define STRAIGHT_SLACK 1e-9
/* The near-coplanar merge threshold eta = min(ETA_TOL tol, max(ETA_DIAG L, ETA_COORD
 * max|x|)) (design 1.3; md_elements_build says why each term). */
#define ETA_TOL 1e-3
#define ETA_DIAG 1e-7
#define ETA_COORD 0x1p-20

static int cmp_xyz(const double *p, const double *q)
{
    for (int c = 0; c < 3; c++)
        if (p[c] != q[c])
            return p[c] < q[c] ? -1 : 1;
    return 0;
}

/* Vertex order: coordinates, then index (only equal coordinates fall back on it). */
static int cmp_vertex(const double *xyz, int64_t a, int64_t b)
{
    int c = cmp_xyz(xyz + 3 * a, xyz + 3 * b);
    return c ? c : (a > b) - (a < b);
}

/* The accurate normal (b - a) x (c - a) of a triangle (not normalised). */
static void tri_normal(const double *xyz, const int64_t *t, double *n)
{
    double u[3], v[3];
    mfg_sub3(xyz + 3 * t[1], xyz + 3 * t[0], u);
    mfg_sub3(xyz + 3 * t[2], xyz + 3 * t[0], v);
    mfg_cross3_accurate(u, v, n);
}

/* ---- sort records ------------------------------------------------------------------- */

typedef struct pair64 {
    int64_t a, b;
    double w; /* payload (corner angle) */
} pair64;

static int cmp_pair(const void *pa, const void *pb)
{
    const pair64 *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->w > y->w) - (x->w < y->w); /* angle sums in an order-free order */
}

/* CSR from sorted (a, b) pairs with duplicates removed: offsets[n + 1], list. */
static int pairs_to_csr(pair64 *p, int64_t np, int64_t n, int64_t **offsets, int64_t **list)
{
    qsort(p, (size_t)np, sizeof *p, cmp_pair);
    int64_t *off = calloc((size_t)n + 2, sizeof *off);
    int64_t *l = malloc((size_t)np * sizeof *l + sizeof *l);
    if (!off || !l) {
        free(off);
        free(l);
        return 0;
    }
    int64_t m = 0;
    for (int64_t i = 0; i < np; i++) {
        if (i > 0 && p[i].a == p[i - 1].a && p[i].b == p[i - 1].b)
            continue;
        l[m++] = p[i].b;
        off[p[i].a + 1]++;
    }
    for (int64_t i = 0; i < n; i++)
        off[i + 1] += off[i];
    *offsets = off;
    *list = l;
    return 1;
}

/* ---- keys for the canonical ids ------------------------------------------------------ */

typedef struct face_key {
    const double *xyz;
    int64_t *verts; /* the face's mesh vertices, sorted by cmp_vertex order of coordinates */
    int64_t nverts;
    double n[3];
    int64_t label; /* provisional face number */
} face_key;

static int cmp_face_key(const void *pa, const void *pb)
{
    const face_key *x = pa, *y = pb;
    int64_t m = x->nverts < y->nverts ? x->nverts : y->nverts;
    for (int64_t i = 0; i < m; i++) {
        int c = cmp_xyz(x->xyz + 3 * x->verts[i], y->xyz + 3 * y->verts[i]);
        if (c)
            return c;
    }
    if (x->nverts != y->nverts)
        return x->nverts < y->nverts ? -1 : 1;
    int c = cmp_xyz(x->n, y->n);
    return c ? c : (x->label > y->label) - (x->label < y->label);
}

typedef struct vsort {
    const double *xyz;
    int64_t v;
} vsort;

static int cmp_vsort(const void *pa, const void *pb)
{
    const vsort *x = pa, *y = pb;
    return cmp_vertex(x->xyz, x->v, y->v);
}

typedef struct edge_key {
    double a[3], b[3];
    int64_t f0, f1;  /* final face ids, ascending */
    int64_t chain;   /* provisional chain number */
} edge_key;

static int cmp_edge_key(const void *pa, const void *pb)
{
    const edge_key *x = pa, *y = pb;
    int c = cmp_xyz(x->a, y->a);
    if (!c)
        c = cmp_xyz(x->b, y->b);
    if (c)
        return c;
    if (x->f0 != y->f0)
        return x->f0 < y->f0 ? -1 : 1;
    if (x->f1 != y->f1)
        return x->f1 < y->f1 ? -1 : 1;
    return (x->chain > y->chain) - (x->chain < y->chain);
}

/* Seeds: decreasing area, ties by the triangle's corners (canonical rotation) in order. */
typedef struct seed {
    const double *xyz;
    const int64_t *tri;
    double area2;
    int64_t t;
} seed;

static int cmp_seed(const void *pa, const void *pb)
{
    const seed *x = pa, *y = pb;
    if (x->area2 != y->area2)
        return x->area2 > y->area2 ? -1 : 1;
    for (int k = 0; k < 3; k++) {
        int c = cmp_xyz(x->xyz + 3 * x->tri[k], y->xyz + 3 * y->tri[k]);
        if (c)
            return c;
    }
    return (x->t > y->t) - (x->t < y->t);
}

/* One mesh edge between two faces, once (stored from its side with the smaller start). */
typedef struct bside {
    int64_t v0, v1;   /* mesh vertices */
    int64_t s0, s1;   /* the two sides 3t + k running v0->v1 and v1->v0 */
    int64_t chain;
} bside;

void md_elements_free(md_elements *el)
{
    if (!el)
        return;
    free(el->xyz);
    free(el->tris);
    free(el->face_plane);
    free(el->face_axis);
    free(el->face_tri_offsets);
    free(el->face_tris);
    free(el->face_side_offsets);
    free(el->face_sides);
    free(el->side_tree_offsets);
    free(el->side_nodes);
    free(el->side_tree_perm);
    free(el->edge_seg);
    free(el->edge_dir);
    free(el->edge_len);
    free(el->edge_faces);
    free(el->edge_w);
    free(el->edge_ends);
    free(el->edge_convex);
    free(el->vert_xyz);
    free(el->vert_mesh);
    free(el->vert_region_empty);
    free(el->bound_offsets);
    free(el->bound);
    free(el->vert_edge_offsets);
    free(el->vert_edges);
    free(el->face_of_triangle);
    free(el->side_elem);
    free(el->corner_elem);
    memset(el, 0, sizeof *el);
}

/* The side of triangle u that runs b -> a (the twin of a side a -> b of its neighbour). */
static int64_t twin_side(const int64_t *tris, int64_t u, int64_t a, int64_t b)
{
    for (int k = 0; k < 3; k++)
        if (tris[3 * u + k] == b && tris[3 * u + (k + 1) % 3] == a)
            return 3 * u + k;
    return -1;
}

/* Is mesh vertex p on the seed plane (exactly, or within eta)? */
static int on_seed_plane(const md_elements *el, const int64_t *seed_tri, const double *plane,
                         int64_t p)
{
    const double *x = el->xyz + 3 * p;
    if (fabs(mfg_dot3(plane, x) - plane[3]) <= el->eta)
        return 1;
    return mfg_orient3d(el->xyz + 3 * seed_tri[0], el->xyz + 3 * seed_tri[1],
                        el->xyz + 3 * seed_tri[2], x) == 0;
}

/* The state of md_elements_build between its phases: the result being built, the input,
 * and the scratch tables (freed by elements_build_scratch_free whatever happens). */
typedef struct elements_build {
    md_elements e;
    const double *xyz;
    const int64_t *triangles;
    int64_t nv, nt;
    int64_t *nbr0, *nbr;      /* neighbour across each side: as checked, then rotated */
    unsigned char *zero;      /* zero-area triangles */
    int64_t *label, *queue;   /* face of each triangle; BFS queue */
    seed *seeds;
    double *plane;            /* 4 per face, before renumbering */
    int64_t *seed_of;         /* seed triangle of each face */
    bside *bs;                /* boundary sides */
    int64_t *bs_off, *bs_list, *vert_elem;
    unsigned char *force;     /* mesh vertices made vertex elements (chain_edges) */
    int64_t *chain_start, *chain_end, *chain_first;
    face_key *fk;
    int64_t *fv;
    vsort *vs;
    edge_key *ek;
    int64_t *face_map, *chain_map, *vert_map, *vchain;
    pair64 *pr;
    int64_t nfaces, nbs, nchains, nvel;
} elements_build;

static mfg_status nomem(const elements_build *mb)
{
    return mfg_fail(MFG_ERR_NOMEM, "out of memory building the medial elements of %lld triangles",
                    (long long)mb->nt);
}

static void elements_build_scratch_free(elements_build *mb)
{
    void *scratch[] = {mb->nbr0, mb->nbr, mb->zero, mb->label, mb->queue, mb->seeds, mb->plane,
                       mb->seed_of, mb->bs, mb->bs_off, mb->bs_list, mb->vert_elem, mb->force,
                       mb->chain_start, mb->chain_end, mb->chain_first, mb->fk, mb->fv, mb->vs,
                       mb->ek, mb->face_map, mb->chain_map, mb->vert_map, mb->vchain, mb->pr};
    for (size_t i = 0; i < sizeof scratch / sizeof *scratch; i++)
        free(scratch[i]);
}

/* The unordered face pair that boundary side i separates. */
static int64_t pair_lo(const elements_build *mb, int64_t i)
{
    int64_t f0 = mb->label[mb->bs[i].s0 / 3], f1 = mb->label[mb->bs[i].s1 / 3];
    return f0 < f1 ? f0 : f1;
}

static int64_t pair_hi(const elements_build *mb, int64_t i)
{
    int64_t f0 = mb->label[mb->bs[i].s0 / 3], f1 = mb->label[mb->bs[i].s1 / 3];
    return f0 < f1 ? f1 : f0;
}

/* Copies the mesh and rotates each triangle so that its smallest corner comes first; the
 * neighbour table rotates with it. */
static mfg_status canonical_triangles(elements_build *mb)
{
    md_elements *e = &mb->e;
    e->nv = mb->nv;
    e->nt = mb->nt;
    e->xyz = malloc((size_t)(3 * mb->nv + 1) * sizeof *e->xyz);
    e->tris = malloc((size_t)(3 * mb->nt + 1) * sizeof *e->tris);
    mb->nbr = malloc((size_t)(3 * mb->nt + 1) * sizeof *mb->nbr);
    mb->zero = calloc((size_t)mb->nt + 1, 1);
    mb->label = malloc((size_t)(mb->nt + 1) * sizeof *mb->label);
    mb->queue = malloc((size_t)(mb->nt + 1) * sizeof *mb->queue);
    mb->seeds = malloc((size_t)(mb->nt + 1) * sizeof *mb->seeds);
    mb->plane = malloc((size_t)(4 * mb->nt + 4) * sizeof *mb->plane);
    mb->seed_of = malloc((size_t)(mb->nt + 1) * sizeof *mb->seed_of);
    if (!e->xyz || !e->tris || !mb->nbr || !mb->zero || !mb->label || !mb->queue || !mb->seeds ||
        !mb->plane || !mb->seed_of)
        return nomem(mb);
    memcpy(e->xyz, mb->xyz, (size_t)(3 * mb->nv) * sizeof *mb->xyz);

    /* Canonical triangles: the smallest corner first, orientation kept; the neighbour
     * table rotates with the sides. */
    for (int64_t t = 0; t < mb->nt; t++) {
        const int64_t *tv = mb->triangles + 3 * t;
        int r = 0;
        for (int k = 1; k < 3; k++)
            if (cmp_vertex(mb->xyz, tv[k], tv[r]) < 0)
                r = k;
        for (int k = 0; k < 3; k++)
            e->tris[3 * t + k] = tv[(k + r) % 3];
    }
    for (int64_t t = 0; t < mb->nt; t++) {
        const int64_t *tv = mb->triangles + 3 * t;
        int r = e->tris[3 * t] == tv[0] ? 0 : (e->tris[3 * t] == tv[1] ? 1 : 2);
        for (int k = 0; k < 3; k++)
            mb->nbr[3 * t + k] = mb->nbr0[3 * t + (k + r) % 3];
    }
    free(mb->nbr0);
    mb->nbr0 = NULL;
    return MFG_OK;
}

/* Grows the faces over the neighbour table (design 1.3). */
static mfg_status grow_faces(elements_build *mb)
{
    md_elements *e = &mb->e;
    mfg_status st;
    /* Faces: BFS from the seeds in order of decreasing area; flatness against the seed's
     * plane (exact orient3d, or within eta), same facing; zero-area triangles bridge. */
    int64_t nseeds = 0;
    for (int64_t t = 0; t < mb->nt; t++) {
        const int64_t *tv = e->tris + 3 * t;
        mb->label[t] = -1;
        mb->zero[t] = (unsigned char)mfg_triangle_zero_area(e->xyz + 3 * tv[0], e->xyz + 3 * tv[1],
                                                        e->xyz + 3 * tv[2]);
        if (!mb->zero[t]) {
            double n[3];
            tri_normal(e->xyz, tv, n);
            mb->seeds[nseeds].xyz = e->xyz;
            mb->seeds[nseeds].tri = tv;
            mb->seeds[nseeds].area2 = mfg_norm3(n);
            mb->seeds[nseeds].t = t;
            nseeds++;
        }
    }
    qsort(mb->seeds, (size_t)nseeds, sizeof *mb->seeds, cmp_seed);
    for (int64_t i = 0; i < nseeds; i++) {
        int64_t s = mb->seeds[i].t;
        if (mb->label[s] >= 0)
            continue;
        const int64_t *sv = e->tris + 3 * s;
        double n[3];
        tri_normal(e->xyz, sv, n);
        double len = mfg_norm3(n);
        double *pl = mb->plane + 4 * mb->nfaces;
        for (int c = 0; c < 3; c++)
            pl[c] = n[c] / len;
        pl[3] = mfg_dot3(pl, e->xyz + 3 * sv[0]);
        mb->seed_of[mb->nfaces] = s;
        int64_t head = 0, tail = 0;
        mb->label[s] = mb->nfaces;
        mb->queue[tail++] = s;
        while (head < tail) {
            int64_t t = mb->queue[head++];
            for (int k = 0; k < 3; k++) {
                int64_t u = mb->nbr[3 * t + k];
                if (mb->label[u] >= 0)
                    continue;
                const int64_t *uv = e->tris + 3 * u;
                int flat = 1;
                for (int j = 0; j < 3 && flat; j++)
                    flat = on_seed_plane(e, sv, pl, uv[j]);
                if (flat && !mb->zero[u]) {
                    double nu[3];
                    tri_normal(e->xyz, uv, nu);
                    flat = mfg_dot3_sign(nu, n) > 0;
                }
                if (flat) {
                    mb->label[u] = mb->nfaces;
                    mb->queue[tail++] = u;
                }
            }
        }
        mb->nfaces++;
    }
    for (int64_t t = 0; t < mb->nt; t++)
        if (mb->label[t] < 0) {
            st = mfg_fail(MFG_ERR_DEGENERATE,
                          "zero-area triangle %lld lies in the plane of none of its neighbours' faces",
                          (long long)t);
            return st;
        }
    return MFG_OK;
}

/* Renumbers the faces canonically; their planes and dominant axes. */
static mfg_status sort_faces(elements_build *mb)
{
    md_elements *e = &mb->e;
    /* Canonical face ids: sorted vertex coordinates of each face. */
    mb->fk = calloc((size_t)mb->nfaces + 1, sizeof *mb->fk);
    mb->fv = malloc((size_t)(3 * mb->nt + 1) * sizeof *mb->fv);
    mb->vs = malloc((size_t)(3 * mb->nt + 1) * sizeof *mb->vs);
    mb->face_map = malloc((size_t)(mb->nfaces + 1) * sizeof *mb->face_map);
    if (!mb->fk || !mb->fv || !mb->vs || !mb->face_map)
        return nomem(mb);
    {
        /* Corners grouped by face (counting sort), then each group sorted and deduplicated. */
        int64_t *cnt = calloc((size_t)mb->nfaces + 2, sizeof *cnt);
        if (!cnt)
            return nomem(mb);
        for (int64_t t = 0; t < mb->nt; t++)
            cnt[mb->label[t] + 1] += 3;
        for (int64_t f = 0; f < mb->nfaces; f++)
            cnt[f + 1] += cnt[f];
        int64_t *pos = mb->queue; /* reuse: nt + 1 >= nfaces slots */
        for (int64_t f = 0; f < mb->nfaces; f++)
            pos[f] = cnt[f];
        for (int64_t t = 0; t < mb->nt; t++)
            for (int k = 0; k < 3; k++) {
                int64_t p = pos[mb->label[t]]++;
                mb->vs[p].xyz = e->xyz;
                mb->vs[p].v = e->tris[3 * t + k];
            }
        for (int64_t f = 0; f < mb->nfaces; f++) {
            int64_t b = cnt[f], n = cnt[f + 1] - cnt[f], m = 0;
            qsort(mb->vs + b, (size_t)n, sizeof *mb->vs, cmp_vsort);
            for (int64_t i = 0; i < n; i++)
                if (m == 0 || mb->fv[b + m - 1] != mb->vs[b + i].v)
                    mb->fv[b + m++] = mb->vs[b + i].v;
            mb->fk[f].xyz = e->xyz;
            mb->fk[f].verts = mb->fv + b;
            mb->fk[f].nverts = m;
            memcpy(mb->fk[f].n, mb->plane + 4 * f, 3 * sizeof(double));
            mb->fk[f].label = f;
        }
        free(cnt);
    }
    qsort(mb->fk, (size_t)mb->nfaces, sizeof *mb->fk, cmp_face_key);
    e->nfaces = mb->nfaces;
    e->face_plane = malloc((size_t)(4 * mb->nfaces) * sizeof *e->face_plane);
    e->face_axis = malloc((size_t)mb->nfaces * sizeof *e->face_axis);
    int64_t *face_seed = malloc((size_t)mb->nfaces * sizeof *face_seed);
    if (!e->face_plane || !e->face_axis || !face_seed) {
        free(face_seed);
        return nomem(mb);
    }
    for (int64_t f = 0; f < mb->nfaces; f++) {
        int64_t old = mb->fk[f].label;
        mb->face_map[old] = f;
        memcpy(e->face_plane + 4 * f, mb->plane + 4 * old, 4 * sizeof(double));
        face_seed[f] = mb->seed_of[old];
        const double *n = e->face_plane + 4 * f;
        int ax = 0;
        for (int c = 1; c < 3; c++)
            if (fabs(n[c]) > fabs(n[ax]))
                ax = c;
        e->face_axis[f] = ax;
    }
    for (int64_t t = 0; t < mb->nt; t++)
        mb->label[t] = mb->face_map[mb->label[t]];
    memcpy(mb->seed_of, face_seed, (size_t)mb->nfaces * sizeof *mb->seed_of);
    free(face_seed);
    return MFG_OK;
}

/* The mesh edges between two faces, their incidence at mesh vertices, and which mesh
 * vertices are vertex elements. */
static mfg_status boundary_graph(elements_build *mb)
{
    md_elements *e = &mb->e;
    /* The boundary graph: mesh edges between two faces, each once. */
    mb->bs = malloc((size_t)(3 * mb->nt + 1) * sizeof *mb->bs);
    if (!mb->bs)
        return nomem(mb);
    for (int64_t t = 0; t < mb->nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t u = mb->nbr[3 * t + k];
            int64_t a = e->tris[3 * t + k], b = e->tris[3 * t + (k + 1) % 3];
            if (mb->label[u] == mb->label[t] || a > b)
                continue;
            bside *q = &mb->bs[mb->nbs++];
            q->v0 = a;
            q->v1 = b;
            q->s0 = 3 * t + k;
            q->s1 = twin_side(e->tris, u, a, b);
            q->chain = -1;
        }
    /* Incidence vertex -> boundary sides (CSR). */
    mb->bs_off = calloc((size_t)mb->nv + 2, sizeof *mb->bs_off);
    mb->bs_list = malloc((size_t)(2 * mb->nbs + 1) * sizeof *mb->bs_list);
    mb->vert_elem = malloc((size_t)(mb->nv + 1) * sizeof *mb->vert_elem);
    if (!mb->bs_off || !mb->bs_list || !mb->vert_elem)
        return nomem(mb);
    for (int64_t i = 0; i < mb->nbs; i++) {
        mb->bs_off[mb->bs[i].v0 + 1]++;
        mb->bs_off[mb->bs[i].v1 + 1]++;
    }
    for (int64_t v = 0; v < mb->nv; v++)
        mb->bs_off[v + 1] += mb->bs_off[v];
    {
        int64_t *pos = malloc((size_t)(mb->nv + 1) * sizeof *pos);
        if (!pos)
            return nomem(mb);
        memcpy(pos, mb->bs_off, (size_t)mb->nv * sizeof *pos);
        for (int64_t i = 0; i < mb->nbs; i++) {
            mb->bs_list[pos[mb->bs[i].v0]++] = i;
            mb->bs_list[pos[mb->bs[i].v1]++] = i;
        }
        free(pos);
    }
    mb->force = calloc((size_t)mb->nv + 1, 1);
    if (!mb->force)
        return nomem(mb);
    return MFG_OK;
}

/* Which mesh vertices are vertex elements: those on boundary sides, except where exactly
 * two sides separating the same two faces meet (inside a chain) and the vertex is not
 * forced (a bend of the chain, chain_edges). */
static void mark_vertex_elements(elements_build *mb)
{
    mb->nvel = 0;
    for (int64_t v = 0; v < mb->nv; v++) {
        int64_t d = mb->bs_off[v + 1] - mb->bs_off[v];
        mb->vert_elem[v] = -1;
        if (d == 0)
            continue;
        if (d == 2 && !mb->force[v]) {
            int64_t i = mb->bs_list[mb->bs_off[v]], j = mb->bs_list[mb->bs_off[v] + 1];
            if (pair_lo(mb, i) == pair_lo(mb, j) && pair_hi(mb, i) == pair_hi(mb, j))
                continue; /* inside a chain */
        }
        mb->vert_elem[v] = mb->nvel++;
    }
}

/* Distance from mesh vertex v to the line through mesh vertices a, b (to a when a = b). */
static double off_line(const elements_build *mb, int64_t v, int64_t a, int64_t b)
{
    const double *X = mb->e.xyz;
    double u[3], d[3];
    mfg_sub3(X + 3 * b, X + 3 * a, u);
    mfg_sub3(X + 3 * v, X + 3 * a, d);
    double len = mfg_norm3(u);
    if (!(len > 0))
        return mfg_norm3(d);
    for (int k = 0; k < 3; k++)
        u[k] /= len;
    double t = mfg_dot3(d, u), x = 0;
    for (int k = 0; k < 3; k++)
        x += (d[k] - t * u[k]) * (d[k] - t * u[k]);
    return sqrt(x);
}

/* Is mesh vertex a ahead of b in ties: the lexicographically smaller point. */
static int vertex_before(const elements_build *mb, int64_t a, int64_t b)
{
    const double *X = mb->e.xyz;
    for (int k = 0; k < 3; k++)
        if (X[3 * a + k] != X[3 * b + k])
            return X[3 * a + k] < X[3 * b + k];
    return a < b;
}

/* Chains the boundary sides into edges between vertex elements (design 1.4).  Two faces
 * merged within eta (design 1.3) need not meet in one straight line: a tessellated curved
 * part's facets, or a bent quad, give a chain that bends at a vertex where the same two
 * faces meet on both sides.  Such a chain is split at its vertex farthest from the line
 * through its ends (made a vertex element), and chaining repeats until every chain is
 * straight within eta (Douglas-Peucker); a closed loop between two faces with no vertex
 * gets one the same way (its lexicographically smallest vertex).  Ties go to the
 * lexicographically smaller vertex, so no split depends on the triangle order. */
static mfg_status chain_edges(elements_build *mb)
{
    mb->chain_start = malloc((size_t)(mb->nbs + 1) * sizeof *mb->chain_start);
    mb->chain_end = malloc((size_t)(mb->nbs + 1) * sizeof *mb->chain_end);
    mb->chain_first = malloc((size_t)(mb->nbs + 1) * sizeof *mb->chain_first);
    int64_t *far = malloc((size_t)(mb->nbs + 1) * sizeof *far);
    double *fard = malloc((size_t)(mb->nbs + 1) * sizeof *fard);
    if (!mb->chain_start || !mb->chain_end || !mb->chain_first || !far || !fard) {
        free(far);
        free(fard);
        return nomem(mb);
    }
    for (;;) {
        mark_vertex_elements(mb);
        mb->nchains = 0;
        for (int64_t i = 0; i < mb->nbs; i++)
            mb->bs[i].chain = -1;
        /* Chains: walk from every vertex element along each unused boundary side. */
        for (int64_t v = 0; v < mb->nv; v++) {
            if (mb->vert_elem[v] < 0)
                continue;
            for (int64_t q = mb->bs_off[v]; q < mb->bs_off[v + 1]; q++) {
                int64_t i = mb->bs_list[q];
                if (mb->bs[i].chain >= 0)
                    continue;
                int64_t c = mb->nchains++, cur = v;
                mb->chain_start[c] = v;
                mb->chain_first[c] = i;
                for (;;) {
                    mb->bs[i].chain = c;
                    int64_t w = mb->bs[i].v0 == cur ? mb->bs[i].v1 : mb->bs[i].v0;
                    if (mb->vert_elem[w] >= 0) {
                        mb->chain_end[c] = w;
                        break;
                    }
                    int64_t i0 = mb->bs_list[mb->bs_off[w]], i1 = mb->bs_list[mb->bs_off[w] + 1];
                    i = i0 == i ? i1 : i0;
                    cur = w;
                }
            }
        }
        int forced = 0;
        /* A closed loop between two faces: its smallest vertex becomes a vertex element. */
        for (int64_t i = 0; i < mb->nbs; i++)
            if (mb->bs[i].chain == -1) {
                int64_t best = mb->bs[i].v0, cur = mb->bs[i].v0, j = i;
                while (mb->bs[j].chain == -1) {
                    mb->bs[j].chain = -2; /* visited */
                    int64_t w = mb->bs[j].v0 == cur ? mb->bs[j].v1 : mb->bs[j].v0;
                    if (vertex_before(mb, w, best))
                        best = w;
                    int64_t i0 = mb->bs_list[mb->bs_off[w]], i1 = mb->bs_list[mb->bs_off[w] + 1];
                    j = i0 == j ? i1 : i0;
                    cur = w;
                }
                mb->force[best] = 1;
                forced = 1;
            }
        /* Each chain's inner vertex farthest from the line through its ends. */
        for (int64_t c = 0; c < mb->nchains; c++) {
            far[c] = -1;
            fard[c] = 0;
        }
        for (int64_t i = 0; i < mb->nbs; i++) {
            int64_t c = mb->bs[i].chain;
            if (c < 0)
                continue;
            for (int j = 0; j < 2; j++) {
                int64_t v = j ? mb->bs[i].v1 : mb->bs[i].v0;
                if (mb->vert_elem[v] >= 0)
                    continue;
                double d = off_line(mb, v, mb->chain_start[c], mb->chain_end[c]);
                if (far[c] < 0 || d > fard[c] || (d == fard[c] && vertex_before(mb, v, far[c]))) {
                    fard[c] = d;
                    far[c] = v;
                }
            }
        }
        for (int64_t c = 0; c < mb->nchains; c++)
            if (far[c] >= 0 && (fard[c] > mb->e.eta || mb->chain_start[c] == mb->chain_end[c])) {
                mb->force[far[c]] = 1;
                forced = 1;
            }
        if (!forced)
            break;
    }
    free(far);
    free(fard);
    return MFG_OK;
}

/* Renumbers the edges and vertices canonically (design 1.6). */
static mfg_status sort_edges_and_vertices(elements_build *mb)
{
    md_elements *e = &mb->e;
    /* Canonical edge ids: (smaller end, larger end, faces). */
    mb->ek = malloc((size_t)(mb->nchains + 1) * sizeof *mb->ek);
    mb->chain_map = malloc((size_t)(mb->nchains + 1) * sizeof *mb->chain_map);
    if (!mb->ek || !mb->chain_map)
        return nomem(mb);
    for (int64_t c = 0; c < mb->nchains; c++) {
        int64_t a = mb->chain_start[c], b = mb->chain_end[c];
        if (cmp_vertex(e->xyz, b, a) < 0) {
            int64_t tmp = a;
            a = b;
            b = tmp;
        }
        mb->chain_start[c] = a;
        mb->chain_end[c] = b;
        memcpy(mb->ek[c].a, e->xyz + 3 * a, sizeof mb->ek[c].a);
        memcpy(mb->ek[c].b, e->xyz + 3 * b, sizeof mb->ek[c].b);
        mb->ek[c].f0 = pair_lo(mb, mb->chain_first[c]);
        mb->ek[c].f1 = pair_hi(mb, mb->chain_first[c]);
        mb->ek[c].chain = c;
    }
    qsort(mb->ek, (size_t)mb->nchains, sizeof *mb->ek, cmp_edge_key);
    for (int64_t i = 0; i < mb->nchains; i++)
        mb->chain_map[mb->ek[i].chain] = i;

    /* Canonical vertex ids: coordinates. */
    mb->vert_map = malloc((size_t)(mb->nv + 1) * sizeof *mb->vert_map);
    if (!mb->vert_map)
        return nomem(mb);
    {
        int64_t m = 0;
        for (int64_t v = 0; v < mb->nv; v++)
            if (mb->vert_elem[v] >= 0) {
                mb->vs[m].xyz = e->xyz;
                mb->vs[m++].v = v;
            }
        qsort(mb->vs, (size_t)m, sizeof *mb->vs, cmp_vsort);
        for (int64_t v = 0; v < mb->nv; v++)
            mb->vert_map[v] = -1;
        for (int64_t i = 0; i < m; i++)
            mb->vert_map[mb->vs[i].v] = i;
    }
    return MFG_OK;
}

/* The edges' segments, in-plane normals and convexity, the vertices' positions. */
static mfg_status edge_geometry(elements_build *mb)
{
    md_elements *e = &mb->e;
    mfg_status st;
    int64_t ne = mb->nchains, nvx = mb->nvel, nF = mb->nfaces;
    e->nedges = ne;
    e->nverts = nvx;
    e->nelements = nF + ne + nvx;
    e->edge_seg = malloc((size_t)(6 * ne + 1) * sizeof *e->edge_seg);
    e->edge_dir = malloc((size_t)(3 * ne + 1) * sizeof *e->edge_dir);
    e->edge_len = malloc((size_t)(ne + 1) * sizeof *e->edge_len);
    e->edge_faces = malloc((size_t)(2 * ne + 1) * sizeof *e->edge_faces);
    e->edge_w = malloc((size_t)(6 * ne + 1) * sizeof *e->edge_w);
    e->edge_ends = malloc((size_t)(2 * ne + 1) * sizeof *e->edge_ends);
    e->edge_convex = malloc((size_t)(ne + 1) * sizeof *e->edge_convex);
    e->vert_xyz = malloc((size_t)(3 * nvx + 1) * sizeof *e->vert_xyz);
    e->vert_mesh = malloc((size_t)(nvx + 1) * sizeof *e->vert_mesh);
    e->vert_region_empty = calloc((size_t)nvx + 1, sizeof *e->vert_region_empty);
    if (!e->edge_seg || !e->edge_dir || !e->edge_len || !e->edge_faces || !e->edge_w ||
        !e->edge_ends || !e->edge_convex || !e->vert_xyz || !e->vert_mesh || !e->vert_region_empty)
        return nomem(mb);
    for (int64_t v = 0; v < mb->nv; v++)
        if (mb->vert_map[v] >= 0) {
            memcpy(e->vert_xyz + 3 * mb->vert_map[v], e->xyz + 3 * v, 3 * sizeof(double));
            e->vert_mesh[mb->vert_map[v]] = v;
        }
    for (int64_t c = 0; c < mb->nchains; c++) {
        int64_t i = mb->chain_map[c];
        double *A = e->edge_seg + 6 * i, *B = A + 3, *u = e->edge_dir + 3 * i;
        memcpy(A, e->xyz + 3 * mb->chain_start[c], 3 * sizeof(double));
        memcpy(B, e->xyz + 3 * mb->chain_end[c], 3 * sizeof(double));
        mfg_sub3(B, A, u);
        double len = mfg_norm3(u);
        for (int k = 0; k < 3; k++)
            u[k] /= len;
        e->edge_len[i] = len;
        e->edge_ends[2 * i] = nF + ne + mb->vert_map[mb->chain_start[c]];
        e->edge_ends[2 * i + 1] = nF + ne + mb->vert_map[mb->chain_end[c]];
        e->edge_faces[2 * i] = pair_lo(mb, mb->chain_first[c]);
        e->edge_faces[2 * i + 1] = pair_hi(mb, mb->chain_first[c]);
        e->edge_convex[i] = -1;
    }
    /* Per boundary side: straightness, the in-plane normals w, convexity. */
    for (int64_t q = 0; q < mb->nbs; q++) {
        int64_t i = mb->chain_map[mb->bs[q].chain];
        const double *A = e->edge_seg + 6 * i, *u = e->edge_dir + 3 * i;
        for (int j = 0; j < 2; j++) {
            double d[3], x = 0;
            mfg_sub3(e->xyz + 3 * (j ? mb->bs[q].v1 : mb->bs[q].v0), A, d);
            double t = mfg_dot3(d, u);
            for (int k = 0; k < 3; k++)
                x += (d[k] - t * u[k]) * (d[k] - t * u[k]);
            if (sqrt(x) > e->eta) {
                st = mfg_fail(MFG_ERR_INTERNAL,
                              "mesh vertex %lld is %g off the line of the edge between faces %lld and %lld (threshold %g)",
                              (long long)(j ? mb->bs[q].v1 : mb->bs[q].v0), sqrt(x),
                              (long long)e->edge_faces[2 * i], (long long)e->edge_faces[2 * i + 1],
                              e->eta);
                return st;
            }
        }
        if (q == mb->chain_first[mb->bs[q].chain]) {
            /* w of each face: n_f x (the side's direction in f's triangle), the interior
             * lying to the left of a counter-clockwise side. */
            for (int j = 0; j < 2; j++) {
                int64_t s = j ? mb->bs[q].s1 : mb->bs[q].s0;
                int64_t f = mb->label[s / 3];
                int64_t a = e->tris[s], b = e->tris[3 * (s / 3) + (s % 3 + 1) % 3];
                double sd[3], w[3];
                mfg_sub3(e->xyz + 3 * b, e->xyz + 3 * a, sd);
                double sgn = mfg_dot3(sd, u) >= 0 ? 1.0 : -1.0;
                double us[3] = {sgn * u[0], sgn * u[1], sgn * u[2]};
                mfg_cross3(e->face_plane + 4 * f, us, w);
                double wl = mfg_norm3(w);
                int slot = f == e->edge_faces[2 * i] ? 0 : 1;
                for (int k = 0; k < 3; k++)
                    e->edge_w[6 * i + 3 * slot + k] = w[k] / wl;
            }
        }
        if (e->edge_convex[i] < 0 && !mb->zero[mb->bs[q].s0 / 3] && !mb->zero[mb->bs[q].s1 / 3]) {
            /* Convex iff the far vertex of Fj's triangle is strictly inside Fi's plane. */
            int64_t ti = mb->bs[q].s0 / 3, tj = mb->bs[q].s1 / 3, sj = mb->bs[q].s1;
            int64_t far = e->tris[3 * tj + (sj % 3 + 2) % 3];
            const int64_t *sv = e->tris + 3 * mb->seed_of[mb->label[ti]];
            int o = mfg_orient3d(e->xyz + 3 * sv[0], e->xyz + 3 * sv[1], e->xyz + 3 * sv[2],
                                 e->xyz + 3 * far);
            if (o != 0)
                e->edge_convex[i] = o > 0;
        }
    }
    for (int64_t i = 0; i < ne; i++)
        if (e->edge_convex[i] < 0) {
            /* No decisive triangle pair (near-coplanar merges or slivers): the normals. */
            const double *ni = e->face_plane + 4 * e->edge_faces[2 * i];
            const double *wj = e->edge_w + 6 * i + 3;
            e->edge_convex[i] = mfg_dot3(ni, wj) < 0;
        }
    return MFG_OK;
}

/* The tables in input order: the face of each triangle, the element of each side and corner. */
static mfg_status triangle_tables(elements_build *mb)
{
    md_elements *e = &mb->e;
    const int64_t nF = e->nfaces, ne = e->nedges;
    /* Tables in input order. */
    e->face_of_triangle = malloc((size_t)(mb->nt + 1) * sizeof *e->face_of_triangle);
    e->side_elem = malloc((size_t)(3 * mb->nt + 1) * sizeof *e->side_elem);
    e->corner_elem = malloc((size_t)(3 * mb->nt + 1) * sizeof *e->corner_elem);
    mb->vchain = malloc((size_t)(mb->nv + 1) * sizeof *mb->vchain);
    if (!e->face_of_triangle || !e->side_elem || !e->corner_elem || !mb->vchain)
        return nomem(mb);
    for (int64_t v = 0; v < mb->nv; v++)
        mb->vchain[v] = -1;
    for (int64_t t = 0; t < mb->nt; t++) {
        e->face_of_triangle[t] = mb->zero[t] ? -1 : mb->label[t];
        for (int k = 0; k < 3; k++)
            e->side_elem[3 * t + k] = mb->label[t];
    }
    for (int64_t q = 0; q < mb->nbs; q++) {
        int64_t id = nF + mb->chain_map[mb->bs[q].chain];
        e->side_elem[mb->bs[q].s0] = id;
        e->side_elem[mb->bs[q].s1] = id;
        mb->vchain[mb->bs[q].v0] = id;
        mb->vchain[mb->bs[q].v1] = id;
    }
    /* A zero-area triangle's corners are collinear: when one of its sides lies on an edge
     * element, all its sides (and their twins) and its non-vertex corners do, whichever
     * face claimed it.  Repeated until nothing changes (slivers in a row).  A corner no
     * chain holds that two slivers on different edges claim (a bent chain split there,
     * or coincident vertices) takes the smaller edge id: every update lowers an id or
     * fills a -1, so the loop ends, whatever the triangle order. */
    unsigned char *claimed = calloc((size_t)mb->nv + 1, 1);
    if (!claimed)
        return nomem(mb);
    for (int changed = 1; changed;) {
        changed = 0;
        for (int64_t t = 0; t < mb->nt; t++) {
            if (!mb->zero[t])
                continue;
            int64_t E = -1;
            for (int k = 0; k < 3; k++)
                if (e->side_elem[3 * t + k] >= nF)
                    E = e->side_elem[3 * t + k];
            if (E < 0)
                continue;
            for (int k = 0; k < 3; k++) {
                int64_t sd = 3 * t + k, v = e->tris[sd], w = e->tris[3 * t + (k + 1) % 3];
                if (e->side_elem[sd] < nF) {
                    int64_t tw = twin_side(e->tris, mb->nbr[sd], v, w);
                    e->side_elem[sd] = E;
                    if (tw >= 0)
                        e->side_elem[tw] = E;
                    changed = 1;
                }
                if (mb->vert_map[v] < 0 &&
                    (mb->vchain[v] < 0 || (claimed[v] && E < mb->vchain[v]))) {
                    mb->vchain[v] = E;
                    claimed[v] = 1;
                    changed = 1;
                }
            }
        }
    }
    free(claimed);
    for (int64_t t = 0; t < mb->nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t v = e->tris[3 * t + k];
            e->corner_elem[3 * t + k] =
                mb->vert_map[v] >= 0 ? nF + ne + mb->vert_map[v]
                                     : (mb->vchain[v] >= 0 ? mb->vchain[v] : mb->label[t]);
        }
    return MFG_OK;
}

/* The faces' triangles and sides, the closures, the edges at each vertex, and the
 * vertices whose region is empty (design 1.7). */
static mfg_status closure_tables(elements_build *mb)
{
    md_elements *e = &mb->e;
    const int64_t nF = e->nfaces, ne = e->nedges, nvx = e->nverts;
    /* Faces' triangles and boundary sides (CSR). */
    mb->pr = malloc((size_t)(8 * ne + 3 * mb->nt + 1) * sizeof *mb->pr);
    if (!mb->pr)
        return nomem(mb);
    {
        int64_t np = 0;
        for (int64_t t = 0; t < mb->nt; t++)
            if (!mb->zero[t])
                mb->pr[np++] = (pair64){mb->label[t], t, 0};
        if (!pairs_to_csr(mb->pr, np, nF, &e->face_tri_offsets, &e->face_tris))
            return nomem(mb);
        np = 0;
        for (int64_t q = 0; q < mb->nbs; q++) {
            mb->pr[np++] = (pair64){mb->label[mb->bs[q].s0 / 3], mb->bs[q].s0, 0};
            mb->pr[np++] = (pair64){mb->label[mb->bs[q].s1 / 3], mb->bs[q].s1, 0};
        }
        if (!pairs_to_csr(mb->pr, np, nF, &e->face_side_offsets, &e->face_sides))
            return nomem(mb);
        /* Closure: a face's edges and their ends; an edge's ends. */
        np = 0;
        for (int64_t i = 0; i < ne; i++) {
            int64_t id = nF + i;
            for (int j = 0; j < 2; j++) {
                int64_t f = e->edge_faces[2 * i + j];
                mb->pr[np++] = (pair64){f, id, 0};
                mb->pr[np++] = (pair64){f, e->edge_ends[2 * i], 0};
                mb->pr[np++] = (pair64){f, e->edge_ends[2 * i + 1], 0};
                mb->pr[np++] = (pair64){id, e->edge_ends[2 * i + j], 0};
            }
        }
        if (!pairs_to_csr(mb->pr, np, e->nelements, &e->bound_offsets, &e->bound))
            return nomem(mb);
        np = 0;
        for (int64_t i = 0; i < ne; i++)
            for (int j = 0; j < 2; j++)
                mb->pr[np++] = (pair64){e->edge_ends[2 * i + j] - nF - ne, nF + i, 0};
        if (!pairs_to_csr(mb->pr, np, nvx, &e->vert_edge_offsets, &e->vert_edges))
            return nomem(mb);
        /* Face corners at vertex elements: the angle sums per (vertex, face). */
        np = 0;
        for (int64_t t = 0; t < mb->nt; t++) {
            if (mb->zero[t])
                continue;
            for (int k = 0; k < 3; k++) {
                int64_t v = e->tris[3 * t + k];
                if (mb->vert_map[v] < 0)
                    continue;
                double a[3], b[3], c[3];
                mfg_sub3(e->xyz + 3 * e->tris[3 * t + (k + 1) % 3], e->xyz + 3 * v, a);
                mfg_sub3(e->xyz + 3 * e->tris[3 * t + (k + 2) % 3], e->xyz + 3 * v, b);
                mfg_cross3(a, b, c);
                mb->pr[np++] = (pair64){mb->vert_map[v], mb->label[t], atan2(mfg_norm3(c), mfg_dot3(a, b))};
            }
        }
        qsort(mb->pr, (size_t)np, sizeof *mb->pr, cmp_pair);
        for (int64_t i = 0; i < np;) {
            int64_t j = i;
            double sum = 0;
            while (j < np && mb->pr[j].a == mb->pr[i].a && mb->pr[j].b == mb->pr[i].b)
                sum += mb->pr[j++].w;
            if (sum >= MFG_PI - STRAIGHT_SLACK)
                e->vert_region_empty[mb->pr[i].a] = 1;
            i = j;
        }
    }
    return MFG_OK;
}

mfg_status md_elements_build(const double *xyz, int64_t nv, const int64_t *triangles,
                             int64_t nt, double tolerance, md_elements *out)
{
    mfg_status st = MFG_OK;
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out (the elements) is NULL");
    memset(out, 0, sizeof *out);
    if (!(tolerance > 0) || !mfg_coord_ok(tolerance))
        return mfg_fail(MFG_ERR_INVALID,
                        "tolerance must be finite and > 0 (and within 2^-200 .. 2^200), got %g",
                        tolerance);
    mfg_mesh_report rep;
    int64_t *nbr0 = NULL;
    st = mfg_mesh_require_closed(xyz, nv, triangles, nt, &rep, &nbr0);
    if (st != MFG_OK)
        return st;
    double ext[3] = {rep.bbox[3] - rep.bbox[0], rep.bbox[4] - rep.bbox[1],
                     rep.bbox[5] - rep.bbox[2]};
    double L = mfg_norm3(ext);
    if (!(tolerance < L)) {
        free(nbr0);
        return mfg_fail(MFG_ERR_INVALID,
                        "tolerance %g must be smaller than the bounding-box diagonal %g",
                        tolerance, L);
    }
    if (L / tolerance > 0x1p20) {
        free(nbr0);
        return mfg_fail(MFG_ERR_INVALID,
                        "tolerance %g is below the bounding-box diagonal %g / 2^20 (the lattice's resolution)",
                        tolerance, L);
    }

    elements_build mb;
    memset(&mb, 0, sizeof mb);
    mb.xyz = xyz;
    mb.triangles = triangles;
    mb.nv = nv;
    mb.nt = nt;
    mb.nbr0 = nbr0;
    mb.e.diag = L;
    /* Near-coplanar merge threshold (design 1.3): tilted faces from float32 STL or OCC are
     * never exactly coplanar.  Float32 rounding grows with the coordinates' magnitude,
     * not with the part's size: a part 100 away from the origin has vertices up to
     * 2^-24 * 140 off, and a small seed triangle tilts its plane by that over its own
     * size, so eta also scales with max|coordinate| (2^-20 of it).  It stays below
     * 1e-3 tolerance: a merged face moves the medial surface by far less than tolerance. */
    double M = 0.0;
    for (int k = 0; k < 6; k++)
        M = fmax(M, fabs(rep.bbox[k]));
    mb.e.eta = fmin(ETA_TOL * tolerance, fmax(ETA_DIAG * L, ETA_COORD * M));
    static mfg_status (*const phase[])(elements_build *) = {
        canonical_triangles, grow_faces, sort_faces, boundary_graph, chain_edges,
        sort_edges_and_vertices, edge_geometry, triangle_tables, closure_tables};
    for (size_t i = 0; i < sizeof phase / sizeof *phase && st == MFG_OK; i++)
        st = phase[i](&mb);
    elements_build_scratch_free(&mb);
    if (st == MFG_OK && !md_side_trees_build(&mb.e))
        st = mfg_fail(MFG_ERR_NOMEM, "md_elements_build: out of memory (side trees)");
    if (st != MFG_OK) {
        md_elements_free(&mb.e);
        return st;
    }
    *out = mb.e;
    return MFG_OK;
}
