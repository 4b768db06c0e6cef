// SPDX-License-Identifier: LGPL-2.1-or-later
// bench_maxisect_cgal.cpp - an exact peer for bench_maxisect: the maximum coverage of spherical convex polygons from CGAL's arrangement of geodesic arcs on the sphere (Arr_geodesic_arc_on_sphere_traits_2, exact kernel), faces' coverage by a walk across the edges.
//
// Every polygon edge is inserted as a geodesic arc carrying (polygon, edge) as consolidated
// curve data.  The coverage of one face is counted directly (a located point), then a
// breadth-first walk crosses each halfedge: for every polygon edge lying on it, the
// polygon is left when its edge runs the same way as the halfedge (polygons are
// counter-clockwise, and an arrangement face lies to the left of its halfedges), entered
// otherwise.  The answer is the largest coverage of a face (sets with interior; a maximum
// reached only on an edge or a vertex is not seen).  A few random points are located
// afterwards and their face coverage checked against a direct count.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <list>
#include <map>
#include <vector>

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_geodesic_arc_on_sphere_traits_2.h>
#include <CGAL/Arr_naive_point_location.h>
#include <CGAL/Arr_spherical_topology_traits_2.h>
#include <CGAL/Arrangement_on_surface_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/version.h>

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Geodesic = CGAL::Arr_geodesic_arc_on_sphere_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<Geodesic, int64_t>;
using Topology = CGAL::Arr_spherical_topology_traits_2<Traits>;
using Arrangement = CGAL::Arrangement_on_surface_2<Traits, Topology>;
using Point = Traits::Point_2;
using Curve = Traits::Curve_2;
using FT = Kernel::FT;

struct Input {
    const double *v;
    const int64_t *off;
    int64_t n;
    // unit normal of edge j of polygon p (interior on its positive side)
    void edge_normal(int64_t p, int64_t j, double out[3]) const
    {
        int64_t k = off[p + 1] - off[p];
        const double *a = v + 3 * (off[p] + j), *b = v + 3 * (off[p] + (j + 1) % k);
        out[0] = a[1] * b[2] - a[2] * b[1];
        out[1] = a[2] * b[0] - a[0] * b[2];
        out[2] = a[0] * b[1] - a[1] * b[0];
    }
    int64_t coverage(const double d[3]) const
    {
        int64_t c = 0;
        for (int64_t p = 0; p < n; p++) {
            int64_t k = off[p + 1] - off[p], j = 0;
            for (; j < k; j++) {
                double nn[3];
                edge_normal(p, j, nn);
                if (d[0] * nn[0] + d[1] * nn[1] + d[2] * nn[2] < 0)
                    break;
            }
            c += j == k;
        }
        return c;
    }
};

// Sign of (halfedge's great-circle normal) . (polygon edge normal): +1 when the polygon
// edge runs the same way as the halfedge.
template <typename Halfedge>
int same_way(const Halfedge &h, const double en[3])
{
    const auto &cv = h->curve();
    const auto &nd = cv.normal();
    bool along = (h->direction() == CGAL::ARR_LEFT_TO_RIGHT) == cv.is_directed_right();
    FT s = nd.dx() * FT(en[0]) + nd.dy() * FT(en[1]) + nd.dz() * FT(en[2]);
    int sg = CGAL::sign(s);
    return along ? sg : -sg;
}

} // namespace

extern "C" const char *mfg_bench_cgal_version(void)
{
    return CGAL_VERSION_STR;
}

// Maximum face coverage; returns 0 on success, -1 on failure (message in err).
extern "C" int mfg_bench_cgal_max_intersection(const double *vertices, const int64_t *offsets,
                                               int64_t n, int64_t *count_out, char *err,
                                               size_t errlen)
{
    try {
        Input in{vertices, offsets, n};
        Traits traits;
        Arrangement arr(&traits);
        auto ctr_p = traits.construct_point_2_object();
        auto ctr_cv = traits.construct_curve_2_object();
        std::list<Curve> curves;
        for (int64_t p = 0; p < n; p++) {
            int64_t k = offsets[p + 1] - offsets[p];
            for (int64_t j = 0; j < k; j++) {
                const double *a = vertices + 3 * (offsets[p] + j);
                const double *b = vertices + 3 * (offsets[p] + (j + 1) % k);
                Point pa = ctr_p(a[0], a[1], a[2]), pb = ctr_p(b[0], b[1], b[2]);
                curves.push_back(Curve(ctr_cv(pa, pb), p * 4096 + j));
            }
        }
        CGAL::insert(arr, curves.begin(), curves.end());

        // a start face: locate a direction and count its coverage directly
        CGAL::Arr_naive_point_location<Arrangement> pl(arr);
        auto face_of = [&](const double d[3], Arrangement::Face_const_handle &f) {
            auto obj = pl.locate(ctr_p(d[0], d[1], d[2]));
            const Arrangement::Face_const_handle *fh =
                boost::get<Arrangement::Face_const_handle>(&obj);
            if (!fh)
                return false;
            f = *fh;
            return true;
        };
        double start[3] = {0.1234567, -0.3456789, 0.9301234};
        Arrangement::Face_const_handle f0;
        if (!face_of(start, f0)) {
            std::snprintf(err, errlen, "the start direction lies on an edge");
            return -1;
        }
        std::map<Arrangement::Face_const_handle, int64_t> cov;
        cov[f0] = in.coverage(start);
        std::deque<Arrangement::Face_const_handle> queue{f0};
        int64_t best = cov[f0];
        while (!queue.empty()) {
            auto f = queue.front();
            queue.pop_front();
            int64_t cf = cov[f];
            auto visit = [&](Arrangement::Halfedge_const_handle h) {
                auto g = h->twin()->face();
                if (cov.count(g))
                    return;
                int64_t delta = 0;
                for (auto it = h->curve().data().begin(); it != h->curve().data().end(); ++it) {
                    double en[3];
                    in.edge_normal(*it / 4096, *it % 4096, en);
                    delta += same_way(h, en) > 0 ? -1 : +1;
                }
                cov[g] = cf + delta;
                best = std::max(best, cf + delta);
                queue.push_back(g);
            };
            for (auto oc = f->outer_ccbs_begin(); oc != f->outer_ccbs_end(); ++oc) {
                auto h = *oc, first = h;
                do {
                    visit(h);
                    h = h->next();
                } while (h != first);
            }
            for (auto ic = f->inner_ccbs_begin(); ic != f->inner_ccbs_end(); ++ic) {
                auto h = *ic, first = h;
                do {
                    visit(h);
                    h = h->next();
                } while (h != first);
            }
        }
        if ((int64_t)cov.size() != (int64_t)arr.number_of_faces()) {
            std::snprintf(err, errlen, "walk reached %lld of %lld faces", (long long)cov.size(),
                          (long long)arr.number_of_faces());
            return -1;
        }
        // self-check: the walk's coverage of a few located directions
        uint64_t s = 99991;
        for (int t = 0; t < 8; t++) {
            double d[3];
            for (int i = 0; i < 3; i++) {
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                d[i] = (double)(s >> 11) * 0x1p-53 * 2 - 1;
            }
            Arrangement::Face_const_handle f;
            if (face_of(d, f) && cov[f] != in.coverage(d)) {
                std::snprintf(err, errlen, "walk coverage %lld != direct count %lld",
                              (long long)cov[f], (long long)in.coverage(d));
                return -1;
            }
        }
        *count_out = best;
        return 0;
    } catch (const std::exception &e) {
        std::snprintf(err, errlen, "CGAL: %s", e.what());
        return -1;
    }
}
