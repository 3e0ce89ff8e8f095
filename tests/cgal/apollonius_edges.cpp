// Delaunay graph of disjoint circles with CGAL's Apollonius_graph_2 (filtered exact predicates),
// the independent peer of curvedvoronoi's diagram construction (tests/test_cgal.py, bench/bench_voronoi.py).
//
// Input (stdin): n, then n lines "x y r" (doubles, taken exactly).
// Output (stdout): "hidden H", "seconds T" (the insertion only), then one line "i j" (0-based input
// indices, i < j) per edge of the Apollonius graph, i.e. per pair of circles sharing a Voronoi edge.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Apollonius_graph_2.h>
#include <CGAL/Apollonius_graph_traits_2.h>
#include <CGAL/Apollonius_graph_filtered_traits_2.h>
#include <chrono>
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

int main() {
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
