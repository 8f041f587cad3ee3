// Regular_triangulation_3 over Epick (exact predicates on double input):
// the 3D side of the backend.
#include "orthomesh/cpp/shim.h"
#include "orthomesh/cpp/regular3.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace orthomesh {

TetrahedralisationOut regular_triangulation_3(rust::Slice<const double> xyzw) {
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  typedef RegularWithIndex3<K> RT3;
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
  return build_and_collect3<RT3>(pts);
}

}  // namespace orthomesh
