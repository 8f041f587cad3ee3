// Shared by the 3D CGAL translation units: Regular_triangulation_3 whose
// vertices carry their input index (hidden points discarded, not kept in
// cells), and its conversion into flat arrays.
#pragma once
#include "orthomesh/cpp/hidden.h"
#include "orthomesh/src/backend/cgal/ffi.rs.h"

#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Regular_triangulation_cell_base_3.h>
#include <CGAL/Regular_triangulation_vertex_base_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace orthomesh {

template <class K>
using RegularWithIndex3 = CGAL::Regular_triangulation_3<
    K, CGAL::Triangulation_data_structure_3<
           CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K, CGAL::Regular_triangulation_vertex_base_3<K>>,
           CGAL::Triangulation_cell_base_with_info_3<
               uint32_t, K,
               CGAL::Regular_triangulation_cell_base_3<K, CGAL::Triangulation_cell_base_3<K>,
                                                       CGAL::Discard_hidden_points>>>>;

// Builds the regular triangulation of (weighted point, index) pairs (range
// insert: spatial sort inside CGAL): positively oriented finite cells as
// index quadruples, their adjacency (neighbour k opposite vertex k, as
// CGAL's), the hidden indices. Throws when the points are coplanar.
template <class RT3>
TetrahedralisationOut build_and_collect3(std::vector<std::pair<typename RT3::Weighted_point, uint32_t>>& pts) {
  const std::size_t n = pts.size();
  RT3 rt(pts.begin(), pts.end());
  if (rt.dimension() < 3)
    throw std::invalid_argument("the points are coplanar: their regular triangulation has no tetrahedron");
  TetrahedralisationOut out;
  for (uint32_t i : hidden_indices(rt, n)) out.hidden.push_back(i);
  auto tets = std::make_unique<std::vector<uint32_t>>();
  auto neighbours = std::make_unique<std::vector<uint32_t>>();
  tets->reserve(4 * rt.number_of_finite_cells());
  neighbours->reserve(4 * rt.number_of_finite_cells());
  uint32_t id = 0;
  for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c) {
    c->info() = id++;
    for (int k = 0; k < 4; ++k) tets->push_back(c->vertex(k)->info());
  }
  for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c)
    for (int k = 0; k < 4; ++k) {
      auto d = c->neighbor(k);
      neighbours->push_back(rt.is_infinite(d) ? UINT32_MAX : d->info());
    }
  out.tets = std::move(tets);
  out.neighbours = std::move(neighbours);
  return out;
}

}  // namespace orthomesh
