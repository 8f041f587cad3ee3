// The bridge header: declarations only, no CGAL include (one CGAL translation
// unit costs ~16 s and 0.7 GB to compile; the cxx bridge TU must stay cheap).
#pragma once
#include "rust/cxx.h"
#include <cstdint>

namespace orthomesh {

struct TriangulationOut;
struct TetrahedralisationOut;

// Regular triangulation of weighted points (x, y, w interleaved), exact
// predicates on double input. Triangles are counter-clockwise, finite only,
// as input indices; `hidden` lists the points that are not vertices.
TriangulationOut regular_triangulation_2(rust::Slice<const double> xyw);

// Constrained Delaunay triangulation of points (x, y interleaved) and
// segments (index pairs). The caller has validated that the segments
// neither cross nor touch except at shared endpoints.
TriangulationOut constrained_delaunay_2(rust::Slice<const double> xy,
                                        rust::Slice<const uint32_t> segments);

// Regular triangulation of exact rational weighted points: `xyw` holds
// 3 tokens per point ("num/den" or integers), whitespace separated.
TriangulationOut regular_triangulation_2_exact(rust::Str xyw);

// Regular triangulation of weighted points in 3D (x, y, z, w interleaved),
// exact predicates on double input: positively oriented finite
// tetrahedra as input indices, their adjacency, the hidden points. Throws
// when the points are coplanar.
TetrahedralisationOut regular_triangulation_3(rust::Slice<const double> xyzw);

// The same for exact rational weighted points: `xyzw` holds 4 tokens per
// point ("num/den" or integers), whitespace separated.
TetrahedralisationOut regular_triangulation_3_exact(rust::Str xyzw);

}  // namespace orthomesh
