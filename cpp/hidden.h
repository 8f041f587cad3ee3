// CGAL-free helper shared by the 2D and 3D collectors.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace orthomesh {

// The input indices 0..n that are no vertex of `tr` (hidden points of a
// regular triangulation, merged duplicates); vertices carry their index
// in info().
template <class Tr>
std::vector<uint32_t> hidden_indices(const Tr& tr, std::size_t n) {
  std::vector<bool> present(n, false);
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
    present.at(v->info()) = true;
  std::vector<uint32_t> out;
  for (std::size_t i = 0; i < n; ++i)
    if (!present[i]) out.push_back(static_cast<uint32_t>(i));
  return out;
}

}  // namespace orthomesh
