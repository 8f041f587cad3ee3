// Regular_triangulation_3 over Epick (exact predicates on double input):
// the 3D side of the backend. Hidden points are discarded, not kept in
// cells (their indices come back in `hidden`).
#include "orthomesh/cpp/shim.h"
#include "orthomesh/src/backend/cgal/ffi.rs.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Regular_triangulation_cell_base_3.h>
#include <CGAL/Regular_triangulation_vertex_base_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace orthomesh {
namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Regular_triangulation_vertex_base_3<K> Vb0;
typedef CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K, Vb0> Vb;
typedef CGAL::Regular_triangulation_cell_base_3<K, CGAL::Triangulation_cell_base_3<K>,
                                                CGAL::Discard_hidden_points>
    Cb0;
typedef CGAL::Triangulation_cell_base_with_info_3<uint32_t, K, Cb0> Cb;
typedef CGAL::Triangulation_data_structure_3<Vb, Cb> Tds;
typedef CGAL::Regular_triangulation_3<K, Tds> RT3;

}  // namespace

TetrahedralisationOut regular_triangulation_3(rust::Slice<const double> xyzw) {
  if (xyzw.size() % 4 != 0) throw std::invalid_argument("xyzw length is not a multiple of 4");
  for (std::size_t i = 0; i < xyzw.size(); ++i)
    if (!std::isfinite(xyzw[i]))
      throw std::invalid_argument("regular triangulation input: value " + std::to_string(i) +
                                  " is not finite");
  const std::size_t n = xyzw.size() / 4;
  std::vector<std::pair<RT3::Weighted_point, uint32_t>> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* v = &xyzw[4 * i];
    pts.emplace_back(RT3::Weighted_point(K::Point_3(v[0], v[1], v[2]), v[3]),
                     static_cast<uint32_t>(i));
  }
  RT3 rt(pts.begin(), pts.end());  // range insert: spatial sort inside CGAL
  if (rt.dimension() < 3)
    throw std::invalid_argument("the points are coplanar: their regular triangulation has no tetrahedron");
  TetrahedralisationOut out;
  std::vector<bool> present(n, false);
  for (auto v = rt.finite_vertices_begin(); v != rt.finite_vertices_end(); ++v)
    present.at(v->info()) = true;
  for (std::size_t i = 0; i < n; ++i)
    if (!present[i]) out.hidden.push_back(static_cast<uint32_t>(i));
  out.tets.reserve(4 * rt.number_of_finite_cells());
  out.neighbours.reserve(4 * rt.number_of_finite_cells());
  uint32_t id = 0;
  for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c) {
    c->info() = id++;
    for (int k = 0; k < 4; ++k) out.tets.push_back(c->vertex(k)->info());
  }
  // CGAL's neighbour k is opposite vertex k, as ours.
  for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c)
    for (int k = 0; k < 4; ++k) {
      auto d = c->neighbor(k);
      out.neighbours.push_back(rt.is_infinite(d) ? UINT32_MAX : d->info());
    }
  return out;
}

}  // namespace orthomesh
