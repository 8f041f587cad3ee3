// Epick (exact predicates, double constructions): the weights step works on
// double points and weights, so exact predicates make every decision exact.
#include "orthomesh/cpp/shim.h"
#include "orthomesh/cpp/collect.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace orthomesh {
namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;

typedef RegularWithIndex2<K> RT;

typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> CVb;
typedef CGAL::Triangulation_face_base_with_info_2<uint32_t, K, CGAL::Constrained_triangulation_face_base_2<K>> CFb;
typedef CGAL::Triangulation_data_structure_2<CVb, CFb> CTds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, CTds, CGAL::Exact_predicates_tag> CDT;
typedef CGAL::Delaunay_triangulation_2<K, CTds> DT;

// CGAL's predicates assume finite input; NaN would break their filters.
void require_finite(rust::Slice<const double> v, const char* what) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(std::string(what) + ": value " + std::to_string(i) + " is not finite");
}

}  // namespace

TriangulationOut regular_triangulation_2(rust::Slice<const double> xyw) {
  if (xyw.size() % 3 != 0) throw std::invalid_argument("xyw length is not a multiple of 3");
  require_finite(xyw, "regular triangulation input");
  const std::size_t n = xyw.size() / 3;
  std::vector<std::pair<RT::Weighted_point, uint32_t>> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    pts.emplace_back(RT::Weighted_point(K::Point_2(xyw[3 * i], xyw[3 * i + 1]), xyw[3 * i + 2]),
                     static_cast<uint32_t>(i));
  }
  RT rt(pts.begin(), pts.end());  // range insert: spatial sort inside CGAL
  return collect(rt, n);
}

TriangulationOut constrained_delaunay_2(rust::Slice<const double> xy,
                                        rust::Slice<const uint32_t> segments) {
  if (xy.size() % 2 != 0) throw std::invalid_argument("xy length is not even");
  if (segments.size() % 2 != 0) throw std::invalid_argument("segments length is not even");
  require_finite(xy, "constrained Delaunay input");
  const std::size_t n = xy.size() / 2;
  std::vector<std::pair<K::Point_2, uint32_t>> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    pts.emplace_back(K::Point_2(xy[2 * i], xy[2 * i + 1]), static_cast<uint32_t>(i));
  }
  // The Delaunay triangulation first: it builds in about 0.6 of the time
  // of CDT's own point insertion, and where it holds every segment (the
  // usual case) it is the constrained one.
  DT dt(pts.begin(), pts.end());
  std::vector<DT::Vertex_handle> handle(n);
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    handle.at(v->info()) = v;
  }
  bool all_edges = true;
  for (std::size_t s = 0; s < segments.size() / 2; ++s) {
    uint32_t a = segments[2 * s], b = segments[2 * s + 1];
    if (a >= n || b >= n) throw std::out_of_range("segment refers to a vertex out of range");
    if (handle[a] == DT::Vertex_handle() || handle[b] == DT::Vertex_handle())
      throw std::invalid_argument("segment endpoint is a duplicate point");
    all_edges = all_edges && dt.is_edge(handle[a], handle[b]);
  }
  if (all_edges) return collect(dt, n);
  // A Delaunay triangulation is a constrained one without constraints: the
  // CDT takes it over (same data structure) and inserts the segments.
  CDT cdt;
  static_cast<CDT::Triangulation&>(cdt).swap(dt);
  for (std::size_t s = 0; s < segments.size() / 2; ++s) {
    cdt.insert_constraint(handle[segments[2 * s]], handle[segments[2 * s + 1]]);
  }
  if (cdt.number_of_vertices() != n)
    throw std::runtime_error("constraints created new vertices: the segments intersect");
  return collect(cdt, n);
}

}  // namespace orthomesh
