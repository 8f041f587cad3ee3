// Epeck (exact constructions, lazy rationals behind an interval filter): the
// site diagram has rational sites and weights, so its input is exact rationals.
#include "orthomesh/cpp/shim.h"
#include "orthomesh/cpp/collect.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace orthomesh {
namespace {

typedef CGAL::Exact_predicates_exact_constructions_kernel K;
typedef K::FT FT;
typedef FT::Exact_type ET;

typedef RegularWithIndex2<K> RT;

FT parse(const std::string& tok) {
  if (tok.empty() || tok.find_first_not_of("+-0123456789/") != std::string::npos)
    throw std::invalid_argument("not a rational number: '" + tok + "'");
  return FT(ET(tok));
}

}  // namespace

TriangulationOut regular_triangulation_2_exact(rust::Str xyw) {
  std::istringstream in(std::string(xyw.data(), xyw.size()));
  std::vector<std::pair<RT::Weighted_point, uint32_t>> pts;
  std::string x, y, w;
  while (in >> x) {
    if (!(in >> y >> w)) throw std::invalid_argument("token count is not a multiple of 3");
    const auto i = static_cast<uint32_t>(pts.size());
    pts.emplace_back(RT::Weighted_point(K::Point_2(parse(x), parse(y)), parse(w)), i);
  }
  const std::size_t n = pts.size();
  RT rt(pts.begin(), pts.end());
  return collect(rt, n);
}

}  // namespace orthomesh
