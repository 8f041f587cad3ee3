//! The cxx bridge: the only place where Rust and the C++ shim meet.
//! Whole slices in, flat index arrays out; every call can throw, so every
//! call returns `Result`.

#[cxx::bridge(namespace = "orthomesh")]
pub(super) mod bridge {
    struct TriangulationOut {
        /// ccw triangles, 3 input indices each (C++ vectors: filled there
        /// without a call into Rust per element)
        triangles: UniquePtr<CxxVector<u32>>,
        /// per triangle, the triangle across its edge k (from its vertex k
        /// to k + 1), u32::MAX on the hull
        neighbours: UniquePtr<CxxVector<u32>>,
        /// input indices that are no vertex of the triangulation
        hidden: Vec<u32>,
    }

    struct TetrahedralisationOut {
        /// positively oriented tetrahedra, 4 input indices each
        tets: UniquePtr<CxxVector<u32>>,
        /// per tetrahedron, the one across the face opposite its vertex k,
        /// u32::MAX on the hull
        neighbours: UniquePtr<CxxVector<u32>>,
        /// input indices that are no vertex of the triangulation
        hidden: Vec<u32>,
    }

    unsafe extern "C++" {
        include!("orthomesh/cpp/shim.h");

        fn regular_triangulation_2(xyw: &[f64]) -> Result<TriangulationOut>;
        fn constrained_delaunay_2(xy: &[f64], segments: &[u32]) -> Result<TriangulationOut>;
        fn regular_triangulation_2_exact(xyw: &str) -> Result<TriangulationOut>;
        fn regular_triangulation_3(xyzw: &[f64]) -> Result<TetrahedralisationOut>;
        fn regular_triangulation_3_exact(xyzw: &str) -> Result<TetrahedralisationOut>;
    }
}
