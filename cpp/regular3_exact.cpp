// Regular_triangulation_3 over Epeck: the 3D site diagram has rational
// sites and weights, so its input is exact rationals.
#include "orthomesh/cpp/shim.h"
#include "orthomesh/cpp/regular3.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace orthomesh {

TetrahedralisationOut regular_triangulation_3_exact(rust::Str xyzw) {
  typedef CGAL::Exact_predicates_exact_constructions_kernel K;
  typedef K::FT FT;
  typedef RegularWithIndex3<K> RT3;
  auto parse = [](const std::string& tok) {
    if (tok.empty() || tok.find_first_not_of("+-0123456789/") != std::string::npos)
      throw std::invalid_argument("not a rational number: '" + tok + "'");
    return FT(FT::Exact_type(tok));
  };
  std::istringstream in(std::string(xyzw.data(), xyzw.size()));
  std::vector<std::pair<RT3::Weighted_point, uint32_t>> pts;
  std::string x, y, z, w;
  while (in >> x) {
    if (!(in >> y >> z >> w)) throw std::invalid_argument("token count is not a multiple of 4");
    const auto i = static_cast<uint32_t>(pts.size());
    pts.emplace_back(RT3::Weighted_point(K::Point_3(parse(x), parse(y), parse(z)), parse(w)), i);
  }
  return build_and_collect3<RT3>(pts);
}

}  // namespace orthomesh
