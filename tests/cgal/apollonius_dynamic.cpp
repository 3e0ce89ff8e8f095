// Insertions and removals in CGAL's Apollonius_graph_2 (filtered exact predicates), the peer of
// curvedvoronoi's local insertion and deletion (tests/test_insertion.py, bench/bench_dynamic.py).
//
// Input (stdin): n, then n lines "x y r" (doubles, taken exactly), built with one insert(begin, end);
// then m, then m operation lines:
//   "+ x y r"   insert a circle; it becomes the last site
//   "- k"       remove site k; sites j > k become j - 1
//   "L k"       remove site k; the last site takes index k
// then optionally q and q lines "x y": nearest-site queries (Apollonius_graph_2::nearest_neighbor).
// Output (stdout): "build T" (seconds of the insertions), one line "op T" per operation (its
// seconds), "hidden H", with queries "queries T" (seconds of all q queries) and one line "nearest k"
// per query, then one line "i j" per edge of the final Apollonius graph (0-based current indices,
// i < j; pairs of circles sharing a Voronoi edge).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Apollonius_graph_2.h>
#include <CGAL/Apollonius_graph_filtered_traits_2.h>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>
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
  for (int i = 0; i < n; ++i) {
    double x, y, r;
    if (std::scanf("%lf %lf %lf", &x, &y, &r) != 3) return 2;
    sites.push_back(Site(Point(x, y), r));
  }
  AG ag;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<AG::Vertex_handle> handle;
  for (const Site &s : sites) handle.push_back(ag.insert(s));   // handles kept for removals
  auto t1 = std::chrono::steady_clock::now();
  std::printf("build %.9f\n", std::chrono::duration<double>(t1 - t0).count());
  int m;
  if (std::scanf("%d", &m) != 1) m = 0;
  for (int q = 0; q < m; ++q) {
    char op[4];
    if (std::scanf("%3s", op) != 1) return 2;
    if (op[0] == '+') {
      double x, y, r;
      if (std::scanf("%lf %lf %lf", &x, &y, &r) != 3) return 2;
      auto a = std::chrono::steady_clock::now();
      AG::Vertex_handle h = ag.insert(Site(Point(x, y), r));
      auto b = std::chrono::steady_clock::now();
      handle.push_back(h);
      std::printf("op %.9f\n", std::chrono::duration<double>(b - a).count());
    } else {
      int k;
      if (std::scanf("%d", &k) != 1) return 2;
      auto a = std::chrono::steady_clock::now();
      ag.remove(handle[k]);
      auto b = std::chrono::steady_clock::now();
      if (op[0] == 'L') {
        handle[k] = handle.back();
        handle.pop_back();
      } else {
        handle.erase(handle.begin() + k);
      }
      std::printf("op %.9f\n", std::chrono::duration<double>(b - a).count());
    }
  }
  std::map<AG::Vertex_handle, int> index;
  int hidden = 0;
  for (int i = 0; i < (int)handle.size(); ++i) {
    if (handle[i] == AG::Vertex_handle()) ++hidden;
    else index[handle[i]] = i;
  }
  std::printf("hidden %d\n", hidden);
  int q;
  if (std::scanf("%d", &q) == 1 && q > 0) {
    std::vector<Point> pts;
    for (int t = 0; t < q; ++t) {
      double x, y;
      if (std::scanf("%lf %lf", &x, &y) != 2) return 2;
      pts.push_back(Point(x, y));
    }
    std::vector<AG::Vertex_handle> got(q);
    auto a = std::chrono::steady_clock::now();
    AG::Vertex_handle hint;
    for (int t = 0; t < q; ++t) got[t] = hint = ag.nearest_neighbor(pts[t], hint);
    auto b = std::chrono::steady_clock::now();
    std::printf("queries %.9f\n", std::chrono::duration<double>(b - a).count());
    for (int t = 0; t < q; ++t) std::printf("nearest %d\n", index[got[t]]);
  }
  std::set<std::pair<int, int>> edges;
  for (auto e = ag.finite_edges_begin(); e != ag.finite_edges_end(); ++e) {
    AG::Face_handle f = e->first;
    int k = e->second;
    int i = index[f->vertex((k + 1) % 3)], j = index[f->vertex((k + 2) % 3)];
    if (i > j) std::swap(i, j);
    edges.insert(std::make_pair(i, j));
  }
  for (const auto &p : edges) std::printf("%d %d\n", p.first, p.second);
  return 0;
}
