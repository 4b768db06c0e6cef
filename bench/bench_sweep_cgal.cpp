// SPDX-License-Identifier: LGPL-2.1-or-later
// bench_sweep_cgal - the CGAL side of bench/bench_sweep.py (issue 20):
//
//   bench_sweep_cgal union <mesh.bin> <N> <theta> <px> <py> <pz> <dx> <dy> <dz> <out.bin>
//                    [epeck|epick] [tree|chain]
//       The peer: the union of N copies of the closed mesh turned about the axis by
//       theta k / (N - 1), k = 0 .. N-1 (theta >= 2 pi: 2 pi k / N), by
//       CGAL::Polygon_mesh_processing::corefine_and_compute_union, in a balanced tree of
//       pairs ("tree", default: neighbouring copies first) or one copy after the other
//       ("chain"); kernel Exact_predicates_exact_constructions_kernel (default: exact
//       points, so the unions can be chained without rounding the intersection points
//       into self-intersections) or ..._inexact_constructions (faster; CGAL warns that
//       chained Booleans may then fail).  Prints one JSON line: the union's time alone
//       (copies built before the clock starts) and its triangles; writes the result
//       (coordinates rounded to double) to out.bin (its volume is computed by the caller:
//       an exact PMP::volume on Epeck points costs more than the union on small inputs).
//
//   bench_sweep_cgal contain <mesh.bin> <points.bin> <out.bin> [eps]
//       The checker: per point, its distance to the triangle soup (AABB tree, exact
//       predicates), signed + when the point is outside (the parity of the triangles that
//       rays in fixed generic directions cross: two, and a third when they disagree), -
//       inside; 0 when the distance is <= eps (on the surface: its side does not matter,
//       so no ray is cast).  It needs no manifold: a result that self-intersects or
//       carries scraps is classified by parity all the same.
//
// Files are little-endian: mesh = int64 nv, int64 nt, double[nv][3], int64[nt][3];
// points = int64 n, double[n][3]; out = double[n].

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

struct Soup {
    std::vector<double> v;        // 3 per vertex
    std::vector<int64_t> t;       // 3 per triangle
};

bool read_mesh(const char *path, Soup &m) {
    FILE *f = std::fopen(path, "rb");
    if (!f) return false;
    int64_t nv = 0, nt = 0;
    bool ok = std::fread(&nv, 8, 1, f) == 1 && std::fread(&nt, 8, 1, f) == 1 && nv >= 0 &&
              nt >= 0;
    if (ok) {
        m.v.resize(size_t(nv) * 3);
        m.t.resize(size_t(nt) * 3);
        ok = std::fread(m.v.data(), 8, m.v.size(), f) == m.v.size() &&
             std::fread(m.t.data(), 8, m.t.size(), f) == m.t.size();
    }
    std::fclose(f);
    for (int64_t i : m.t)
        if (i < 0 || i * 3 >= int64_t(m.v.size())) return false;
    return ok;
}

bool write_mesh(const char *path, const Soup &m) {
    FILE *f = std::fopen(path, "wb");
    if (!f) return false;
    int64_t nv = int64_t(m.v.size() / 3), nt = int64_t(m.t.size() / 3);
    bool ok = std::fwrite(&nv, 8, 1, f) == 1 && std::fwrite(&nt, 8, 1, f) == 1 &&
              std::fwrite(m.v.data(), 8, m.v.size(), f) == m.v.size() &&
              std::fwrite(m.t.data(), 8, m.t.size(), f) == m.t.size();
    return std::fclose(f) == 0 && ok;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class K>
int run_union(const Soup &in, int n, double theta, const double p[3], const double d[3],
              const char *out, bool tree, const char *kernel) {
    using Point = typename K::Point_3;
    using Mesh = CGAL::Surface_mesh<Point>;
    using VI = typename Mesh::Vertex_index;
    double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double a[3] = {d[0] / len, d[1] / len, d[2] / len};
    bool full = theta >= 2 * M_PI * (1 - 1e-12);
    std::vector<Mesh> parts(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
        double ang = full ? 2 * M_PI * k / n : (n > 1 ? theta * k / (n - 1) : 0.0);
        double c = std::cos(ang), s = std::sin(ang);
        Mesh &m = parts[size_t(k)];
        std::vector<VI> vid(in.v.size() / 3);
        for (size_t i = 0; i < vid.size(); ++i) {
            // Rodrigues: x' = x c + (a x x) s + a (a . x)(1 - c), about the axis point
            double x[3] = {in.v[3 * i] - p[0], in.v[3 * i + 1] - p[1], in.v[3 * i + 2] - p[2]};
            double ax[3] = {a[1] * x[2] - a[2] * x[1], a[2] * x[0] - a[0] * x[2],
                            a[0] * x[1] - a[1] * x[0]};
            double dot = a[0] * x[0] + a[1] * x[1] + a[2] * x[2];
            double y[3];
            for (int j = 0; j < 3; ++j) y[j] = x[j] * c + ax[j] * s + a[j] * dot * (1 - c) + p[j];
            vid[i] = m.add_vertex(Point(y[0], y[1], y[2]));
        }
        for (size_t i = 0; i < in.t.size(); i += 3)
            if (m.add_face(vid[size_t(in.t[i])], vid[size_t(in.t[i + 1])],
                           vid[size_t(in.t[i + 2])]) == Mesh::null_face()) {
                std::fprintf(stderr, "bench_sweep_cgal: the input is not a 2-manifold mesh\n");
                return 2;
            }
    }
    auto t0 = std::chrono::steady_clock::now();
    bool ok = true;
    if (tree) {
        while (parts.size() > 1) {
            std::vector<Mesh> next;
            for (size_t i = 0; i < parts.size(); i += 2) {
                if (i + 1 == parts.size()) {
                    next.push_back(std::move(parts[i]));
                    continue;
                }
                Mesh u;
                ok = PMP::corefine_and_compute_union(parts[i], parts[i + 1], u) && ok;
                next.push_back(std::move(u));
            }
            parts.swap(next);
        }
    } else {
        for (size_t i = 1; i < parts.size(); ++i) {
            Mesh u;
            ok = PMP::corefine_and_compute_union(parts[0], parts[i], u) && ok;
            parts[0] = std::move(u);
        }
        parts.resize(1);
    }
    double secs = seconds_since(t0);
    const Mesh &r = parts[0];
    Soup res;
    std::vector<int64_t> index(r.number_of_vertices() + r.number_of_removed_vertices(), -1);
    for (VI v : r.vertices()) {
        index[size_t(v)] = int64_t(res.v.size() / 3);
        const Point &q = r.point(v);
        res.v.push_back(CGAL::to_double(q.x()));
        res.v.push_back(CGAL::to_double(q.y()));
        res.v.push_back(CGAL::to_double(q.z()));
    }
    for (auto f : r.faces()) {
        int cnt = 0;
        for (VI v : CGAL::vertices_around_face(r.halfedge(f), r)) {
            res.t.push_back(index[size_t(v)]);
            ++cnt;
        }
        if (cnt != 3) {
            std::fprintf(stderr, "bench_sweep_cgal: a non-triangle face in the union\n");
            return 2;
        }
    }
    if (!write_mesh(out, res)) {
        std::fprintf(stderr, "bench_sweep_cgal: cannot write %s\n", out);
        return 2;
    }
    std::printf("{\"s\": %.6f, \"triangles\": %zu, \"vertices\": %zu, "
                "\"ok\": %s, \"kernel\": \"%s\", \"order\": \"%s\"}\n",
                secs, res.t.size() / 3, res.v.size() / 3, ok ? "true" : "false",
                kernel, tree ? "tree" : "chain");
    return ok ? 0 : 3;
}

int run_contain(const Soup &m, const char *points_path, const char *out, double eps) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Tri = K::Triangle_3;
    using Prim = CGAL::AABB_triangle_primitive<K, std::vector<Tri>::const_iterator>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>>;
    std::vector<Tri> tris;
    tris.reserve(m.t.size() / 3);
    for (size_t i = 0; i < m.t.size(); i += 3) {
        auto P = [&](int64_t k) { return K::Point_3(m.v[3 * k], m.v[3 * k + 1], m.v[3 * k + 2]); };
        Tri t(P(m.t[i]), P(m.t[i + 1]), P(m.t[i + 2]));
        if (!t.is_degenerate()) tris.push_back(t);   // zero area: crosses no ray
    }
    FILE *f = std::fopen(points_path, "rb");
    int64_t n = 0;
    std::vector<double> pts;
    bool ok = f && std::fread(&n, 8, 1, f) == 1 && n >= 0;
    if (ok) {
        pts.resize(size_t(n) * 3);
        ok = std::fread(pts.data(), 8, pts.size(), f) == pts.size();
    }
    if (f) std::fclose(f);
    if (!ok) {
        std::fprintf(stderr, "bench_sweep_cgal: cannot read %s\n", points_path);
        return 2;
    }
    std::vector<double> dist(size_t(n), 0.0);
    if (!tris.empty()) {
        Tree tree(tris.cbegin(), tris.cend());
        tree.accelerate_distance_queries();
        const K::Vector_3 dirs[3] = {K::Vector_3(0.5377, 0.3141, 0.7826),
                                     K::Vector_3(-0.6123, 0.7071, 0.3536),
                                     K::Vector_3(0.2113, -0.8820, -0.4212)};
        for (int64_t i = 0; i < n; ++i) {
            K::Point_3 q(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
            double dd = std::sqrt(CGAL::to_double(tree.squared_distance(q)));
            if (dd <= eps) {            // on the surface: inside or out does not matter
                dist[size_t(i)] = 0.0;
                continue;
            }
            int outside = 0, rays = 0;
            for (const auto &dv : dirs) {
                outside += tree.number_of_intersected_primitives(K::Ray_3(q, dv)) % 2 == 0;
                ++rays;
                if (rays == 2 && outside != 1) break;     // two agree: the majority
            }
            dist[size_t(i)] = outside >= 2 ? dd : -dd;
        }
    } else {
        for (auto &x : dist) x = HUGE_VAL;
    }
    FILE *o = std::fopen(out, "wb");
    if (!o || std::fwrite(dist.data(), 8, dist.size(), o) != dist.size() || std::fclose(o) != 0) {
        std::fprintf(stderr, "bench_sweep_cgal: cannot write %s\n", out);
        return 2;
    }
    std::printf("{\"points\": %lld, \"triangles\": %zu}\n", (long long)n, tris.size());
    return 0;
}

int usage() {
    std::fprintf(stderr,
                 "usage: bench_sweep_cgal union <mesh.bin> <N> <theta> <px> <py> <pz> <dx> <dy> "
                 "<dz> <out.bin> [epeck|epick] [tree|chain]\n"
                 "       bench_sweep_cgal contain <mesh.bin> <points.bin> <out.bin> [eps]\n");
    return 2;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 2) return usage();
    try {
        Soup m;
        if (!std::strcmp(argv[1], "union") && argc >= 12) {
            if (!read_mesh(argv[2], m)) {
                std::fprintf(stderr, "bench_sweep_cgal: cannot read %s\n", argv[2]);
                return 2;
            }
            int n = std::atoi(argv[3]);
            double theta = std::atof(argv[4]);
            double p[3] = {std::atof(argv[5]), std::atof(argv[6]), std::atof(argv[7])};
            double d[3] = {std::atof(argv[8]), std::atof(argv[9]), std::atof(argv[10])};
            std::string kernel = argc > 12 ? argv[12] : "epeck";
            bool tree = !(argc > 13 && !std::strcmp(argv[13], "chain"));
            if (n < 1) return usage();
            if (kernel == "epick")
                return run_union<CGAL::Exact_predicates_inexact_constructions_kernel>(
                    m, n, theta, p, d, argv[11], tree, "epick");
            return run_union<CGAL::Exact_predicates_exact_constructions_kernel>(
                m, n, theta, p, d, argv[11], tree, "epeck");
        }
        if (!std::strcmp(argv[1], "contain") && (argc == 5 || argc == 6)) {
            if (!read_mesh(argv[2], m)) {
                std::fprintf(stderr, "bench_sweep_cgal: cannot read %s\n", argv[2]);
                return 2;
            }
            return run_contain(m, argv[3], argv[4], argc == 6 ? std::atof(argv[5]) : 0.0);
        }
    } catch (const std::bad_alloc &) {
        std::fprintf(stderr, "bench_sweep_cgal: out of memory (std::bad_alloc)\n");
        return 4;
    } catch (const std::exception &e) {
        std::fprintf(stderr, "bench_sweep_cgal: %s\n", e.what());
        return 3;
    }
    return usage();
}
