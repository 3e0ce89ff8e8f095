// Delaunay graph of disjoint circles with CGAL's Apollonius_graph_2 (filtered exact predicates),
// the independent peer of curvedvoronoi's diagram construction (tests/test_cgal.py, bench/bench_voronoi.py).
//
// Input (stdin): n, then n lines "x y r" (doubles, taken exactly).
// Output (stdout): "hidden H", "seconds T" (the insertion only), then one line "i j" (0-based input
// indices, i < j) per edge of the Apollonius graph, i.e. per pair of circles sharing a Voronoi edge.
//
// With the argument --degenerate: one line "i j D L" per edge of the triangulation instead (a pair
// may appear more than once), D = 1 when CGAL's exact predicate Is_degenerate_edge_2 (the traits
// functor behind the protected Apollonius_graph_2::is_degenerate_edge(Edge)) says the dual Voronoi
// edge has length zero (its two Apollonius circles coincide: co-circular input), else 0; L = the
// distance between the two dual vertices in double precision (EPICK constructions, approximate;
// "inf" when one of the two faces is infinite, i.e. the Voronoi edge is unbounded).  Edges next to
// an infinite face are never degenerate (their dual is a ray or a line).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Apollonius_graph_2.h>
#include <CGAL/Apollonius_graph_traits_2.h>
#include <CGAL/Apollonius_graph_filtered_traits_2.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Apollonius_graph_filtered_traits_2<K> Traits;
typedef CGAL::Apollonius_graph_2<Traits> AG;
typedef AG::Site_2 Site;
typedef AG::Point_2 Point;

int main(int argc, char **argv) {
  bool degenerate_mode = argc > 1 && std::strcmp(argv[1], "--degenerate") == 0;
  int n;
  if (std::scanf("%d", &n) != 1) return 2;
  std::vector<Site> sites;
  std::map<std::tuple<double, double, double>, int> index;
  for (int i = 0; i < n; ++i) {
    double x, y, r;
    if (std::scanf("%lf %lf %lf", &x, &y, &r) != 3) return 2;
    sites.push_back(Site(Point(x, y), r));
    index[std::make_tuple(x, y, r)] = i;
  }
  auto t0 = std::chrono::steady_clock::now();
  AG ag;
  ag.insert(sites.begin(), sites.end());
  auto t1 = std::chrono::steady_clock::now();
  if (degenerate_mode) {
    std::map<AG::Face_handle, Site> duals;
    for (auto f = ag.finite_faces_begin(); f != ag.finite_faces_end(); ++f) duals[AG::Face_handle(f)] = ag.dual(f);
    std::printf("hidden %d\n", (int)(n - ag.number_of_vertices()));
    std::printf("seconds %.9f\n", std::chrono::duration<double>(t1 - t0).count());
    for (auto e = ag.finite_edges_begin(); e != ag.finite_edges_end(); ++e) {
      AG::Face_handle f = e->first;
      int k = e->second;
      AG::Face_handle g = f->neighbor(k);
      Site a = f->vertex((k + 1) % 3)->site(), b = f->vertex((k + 2) % 3)->site();
      int i = index[std::make_tuple(a.point().x(), a.point().y(), a.weight())];
      int j = index[std::make_tuple(b.point().x(), b.point().y(), b.weight())];
      if (i > j) std::swap(i, j);
      bool finite = !ag.is_infinite(f) && !ag.is_infinite(g);
      bool degenerate = finite && ag.geom_traits().is_degenerate_edge_2_object()(
          f->vertex((k + 1) % 3)->site(), f->vertex((k + 2) % 3)->site(), f->vertex(k)->site(),
          ag.tds().mirror_vertex(f, k)->site());
      double len = HUGE_VAL;
      if (finite) {
        Point p = duals[f].point(), q = duals[g].point();
        len = std::sqrt(CGAL::to_double(CGAL::squared_distance(p, q)));
      }
      if (finite) std::printf("%d %d %d %.17g\n", i, j, degenerate ? 1 : 0, len);
      else std::printf("%d %d 0 inf\n", i, j);
    }
    return 0;
  }
  std::set<std::pair<int, int>> edges;
  for (auto e = ag.finite_edges_begin(); e != ag.finite_edges_end(); ++e) {
    AG::Face_handle f = e->first;
    int k = e->second;
    Site a = f->vertex((k + 1) % 3)->site(), b = f->vertex((k + 2) % 3)->site();
    int i = index[std::make_tuple(a.point().x(), a.point().y(), a.weight())];
    int j = index[std::make_tuple(b.point().x(), b.point().y(), b.weight())];
    if (i > j) std::swap(i, j);
    edges.insert(std::make_pair(i, j));
  }
  std::printf("hidden %d\n", (int)(n - ag.number_of_vertices()));
  std::printf("seconds %.9f\n", std::chrono::duration<double>(t1 - t0).count());
  for (auto &p : edges) std::printf("%d %d\n", p.first, p.second);
  return 0;
}
