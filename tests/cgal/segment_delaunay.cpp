// Delaunay graph of points and non-crossing segments with CGAL's Segment_Delaunay_graph_2 (exact
// filtered predicates), the independent peer of the segment-site diagram (tests/cgal/sdg_peer.py,
// tests/test_segment_peers.py).
//
// CGAL splits a closed input segment [p, q] into three sites: the points p and q and the open
// segment; an endpoint shared by several input segments (or equal to an input point) is one site.
//
// Input (stdin): n, then n lines "x0 y0 x1 y1" (doubles, taken exactly); a line with x0 == x1 and
// y0 == y1 is a point site, any other line a segment.  The segments must not cross, overlap or
// touch each other except at common endpoints, and no point may lie in a segment's interior (the
// traits are the "without intersections" ones).
// Output (stdout): one line per finite edge of the triangulation (both vertices finite; a pair of
// sites may appear more than once: the segment Delaunay graph can have multi-edges), the two sites
// written "p x y" or "s x0 y0 x1 y1", separated by " | ".  Coordinates are printed with %.17g, exact
// for every double (integers up to 2^53 print as integers).
// stderr: "seconds T", the insertion time alone (and, with --degenerate, "exact_constructions N").
//
// With the argument --degenerate each line ends with " | D", D = 1 when the dual Voronoi edge has
// length zero: both adjacent faces are finite and their Voronoi vertices are equal.  The vertices
// are constructed with Segment_Delaunay_graph_traits_without_intersections_2 (Field_with_sqrt_tag)
// first over intervals (disjoint boxes: distinct), else over CORE::Expr (exact square roots, exact
// comparison).  These are the diagonals a triangulation adds at a Voronoi vertex of degree >= 4.
// Edges next to an infinite face are never degenerate (their dual is unbounded).
//
// CGAL's predicate Is_degenerate_edge_2 (the traits functor behind the protected
// Segment_Delaunay_graph_2::is_degenerate_edge(Edge): "the fourth site is not outside the Voronoi
// circle of the other three, both ways round") is NOT used: it errs both ways on segment scenes.
//  * When the two faces have the same third vertex (a multi-edge: faces (p, q, r) and (q, p, r), two
//    distinct circles tangent to the same three sites) the fourth site is the third, lies on the
//    circle, and the predicate says "degenerate" for an edge of positive length (random scenes:
//    an endpoint p, its own segment r and a segment q).
//  * When the circle of (p, q, r) passes through the endpoint of a segment s = fourth site and
//    is centred on the perpendicular to s there (s touches the circle at its endpoint only), the
//    open segment is "outside" and the predicate says "not degenerate", while the Voronoi vertex
//    of (q, p, s) is that same centre (the segment is at the distance of its endpoint), so the
//    edge has length zero (random scenes, 1e5 segments: points (11375, 7611), (11403, 7627),
//    (11389, 7645), segment (11403, 7619)-(11403, 7627); Boost omits that edge).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Segment_Delaunay_graph_2.h>
#include <CGAL/Segment_Delaunay_graph_filtered_traits_2.h>
#include <CGAL/Segment_Delaunay_graph_traits_2.h>
#include <CGAL/CORE_Expr.h>
#include <CGAL/Interval_nt.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

// The combination of the CGAL manual's examples (sdg-count-sites.cpp, sdg-info-set.cpp): double
// input, square-root-field constructions, filtered exact predicates (interval arithmetic first, then
// Gmpq/MP_Float with the ring method).
typedef CGAL::Simple_cartesian<double> K;
typedef CGAL::Segment_Delaunay_graph_filtered_traits_without_intersections_2<K, CGAL::Field_with_sqrt_tag> Gt;
typedef CGAL::Segment_Delaunay_graph_2<Gt> SDG;
typedef SDG::Site_2 Site;
typedef SDG::Point_2 Point;

// Constructions of Voronoi vertices: intervals, then exact.
typedef CGAL::Simple_cartesian<CGAL::Interval_nt<false>> IK;
typedef CGAL::Segment_Delaunay_graph_traits_without_intersections_2<IK, CGAL::Field_with_sqrt_tag> IGt;
typedef CGAL::Simple_cartesian<CORE::Expr> EK;
typedef CGAL::Segment_Delaunay_graph_traits_without_intersections_2<EK, CGAL::Field_with_sqrt_tag> EGt;

template <class Gt>
static typename Gt::Site_2 convert_site(const Site &s) {
  typedef typename Gt::Site_2 S;
  typedef typename Gt::Point_2 P;
  if (s.is_point()) return S::construct_site_2(P(s.point().x(), s.point().y()));
  return S::construct_site_2(P(s.source().x(), s.source().y()), P(s.target().x(), s.target().y()));
}

template <class Gt>
static typename Gt::Point_2 voronoi_vertex(SDG::Face_handle f) {
  Gt gt;
  return gt.construct_svd_vertex_2_object()(convert_site<Gt>(f->vertex(0)->site()),
                                            convert_site<Gt>(f->vertex(1)->site()),
                                            convert_site<Gt>(f->vertex(2)->site()));
}

struct Dual {
  bool interval_tried = false, interval_ok = false;
  IK::Point_2 box;
  bool exact_done = false;
  EK::Point_2 exact;
};

static long exact_constructions = 0;

// The Voronoi vertices of the finite faces f and g are equal.
static bool same_voronoi_vertex(std::map<SDG::Face_handle, Dual> &cache, SDG::Face_handle f, SDG::Face_handle g) {
  Dual *d[2] = {&cache[f], &cache[g]};
  SDG::Face_handle h[2] = {f, g};
  {
    CGAL::Protect_FPU_rounding<true> protect;
    for (int i = 0; i < 2; ++i) {
      if (d[i]->interval_tried) continue;
      d[i]->interval_tried = true;
      try {
        d[i]->box = voronoi_vertex<IGt>(h[i]);
        d[i]->interval_ok = true;
      } catch (CGAL::Uncertain_conversion_exception &) {
        // a branch of the construction undecided on intervals: exact below
      }
    }
    if (d[0]->interval_ok && d[1]->interval_ok) {
      const IK::Point_2 &a = d[0]->box, &b = d[1]->box;
      if (!a.x().do_overlap(b.x()) || !a.y().do_overlap(b.y())) return false;
    }
  }
  for (int i = 0; i < 2; ++i) {
    if (!d[i]->exact_done) {
      d[i]->exact = voronoi_vertex<EGt>(h[i]);
      ++exact_constructions;
      d[i]->exact_done = true;
    }
  }
  return d[0]->exact.x() == d[1]->exact.x() && d[0]->exact.y() == d[1]->exact.y();
}

static void print_site(const Site &s) {
  if (s.is_point()) {
    Point p = s.point();
    std::printf("p %.17g %.17g", p.x(), p.y());
  } else {
    Point a = s.source(), b = s.target();
    std::printf("s %.17g %.17g %.17g %.17g", a.x(), a.y(), b.x(), b.y());
  }
}

int main(int argc, char **argv) {
  bool degenerate_mode = argc > 1 && std::strcmp(argv[1], "--degenerate") == 0;
  int n;
  if (std::scanf("%d", &n) != 1) return 2;
  std::vector<Point> points;
  std::vector<std::pair<std::size_t, std::size_t>> segments;
  for (int i = 0; i < n; ++i) {
    double x0, y0, x1, y1;
    if (std::scanf("%lf %lf %lf %lf", &x0, &y0, &x1, &y1) != 4) return 2;
    points.push_back(Point(x0, y0));
    if (x0 != x1 || y0 != y1) {
      points.push_back(Point(x1, y1));
      segments.push_back(std::make_pair(points.size() - 2, points.size() - 1));
    }
  }
  auto t0 = std::chrono::steady_clock::now();
  SDG sdg;
  // Spatially sorted insertion of all the points (isolated ones and segment endpoints; a repeated
  // point returns the existing vertex), then of the segments between their endpoint vertices.
  sdg.insert_segments(points, segments.begin(), segments.end());
  auto t1 = std::chrono::steady_clock::now();
  std::fprintf(stderr, "seconds %.9f\n", std::chrono::duration<double>(t1 - t0).count());
  if (!sdg.is_valid()) {
    std::fprintf(stderr, "invalid segment Delaunay graph\n");
    return 3;
  }
  std::map<SDG::Face_handle, Dual> duals;
  for (auto e = sdg.finite_edges_begin(); e != sdg.finite_edges_end(); ++e) {
    SDG::Face_handle f = e->first;
    int k = e->second;
    print_site(f->vertex(SDG::ccw(k))->site());
    std::printf(" | ");
    print_site(f->vertex(SDG::cw(k))->site());
    if (degenerate_mode) {
      bool degenerate = false;
      if (sdg.dimension() == 2) {
        SDG::Face_handle g = f->neighbor(k);
        if (!sdg.is_infinite(f) && !sdg.is_infinite(g)) degenerate = same_voronoi_vertex(duals, f, g);
      }
      std::printf(" | %d", degenerate ? 1 : 0);
    }
    std::printf("\n");
  }
  if (degenerate_mode) std::fprintf(stderr, "exact_constructions %ld\n", exact_constructions);
  return 0;
}
