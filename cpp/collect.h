// Shared by the CGAL translation units (never by the bridge header): the
// regular triangulation whose vertices carry their input index, and its
// conversion into flat arrays.
#pragma once
#include "orthomesh/cpp/hidden.h"
#include "orthomesh/src/backend/cgal/ffi.rs.h"
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace orthomesh {

// Regular_triangulation_2 over kernel K, vertices tagged with input
// indices, faces with room for their output index.
template <class K>
using RegularWithIndex2 = CGAL::Regular_triangulation_2<
    K, CGAL::Triangulation_data_structure_2<
           CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K, CGAL::Regular_triangulation_vertex_base_2<K>>,
           CGAL::Triangulation_face_base_with_info_2<uint32_t, K, CGAL::Regular_triangulation_face_base_2<K>>>>;

// Finite faces as ccw index triples with their adjacency, plus the indices
// that are no vertex (hidden points of a regular triangulation, merged
// duplicates). Numbers the finite faces in their info.
template <class Tr>
TriangulationOut collect(Tr& tr, std::size_t n) {
  TriangulationOut out;
  for (uint32_t i : hidden_indices(tr, n)) out.hidden.push_back(i);
  auto triangles = std::make_unique<std::vector<uint32_t>>();
  auto neighbours = std::make_unique<std::vector<uint32_t>>();
  if (tr.dimension() == 2) {
    triangles->reserve(3 * tr.number_of_faces());
    neighbours->reserve(3 * tr.number_of_faces());
    uint32_t id = 0;
    for (auto f = tr.finite_faces_begin(); f != tr.finite_faces_end(); ++f) {
      f->info() = id++;
      for (int k = 0; k < 3; ++k) triangles->push_back(f->vertex(k)->info());
    }
    // CGAL's neighbour i is opposite vertex i: across our edge k (vertex k
    // to k + 1) lies neighbour (k + 2) % 3.
    for (auto f = tr.finite_faces_begin(); f != tr.finite_faces_end(); ++f) {
      for (int k = 0; k < 3; ++k) {
        auto g = f->neighbor((k + 2) % 3);
        neighbours->push_back(tr.is_infinite(g) ? UINT32_MAX : g->info());
      }
    }
  }
  out.triangles = std::move(triangles);
  out.neighbours = std::move(neighbours);
  return out;
}

}  // namespace orthomesh
