//! Shared helpers for the 3D hybrid's tests: building with sites outside
//! allowed, and writing meshes for tests/readers.py.

use orthomesh::backend::compiled;
use orthomesh::reservoir::hybrid3::{build, Hybrid3, Hybrid3Options, Well3};
use orthomesh::reservoir::CornerPointGrid;
use std::path::Path;

/// Writes a mesh as `hybrid3-{stem}` for tests/readers.py.
pub fn write(stem: &str, h: &Hybrid3) {
    write_as(&format!("hybrid3-{stem}"), h);
}

/// Meshes beside faults where vtk still flags a few transition cells
/// (emerald): tests/readers.py reads them and counts those
/// (docs/limitations.md). Named by backend, as the suite runs them on each.
pub fn write_faulted(stem: &str, h: &Hybrid3) {
    write_as(&format!("faulted3-{stem}-{}", compiled()[0].name()), h);
}

/// Writes a mesh's VTU and TOUGH MESH under `$ORTHOMESH_TEST_OUT`, if set.
pub fn write_as(name: &str, h: &Hybrid3) {
    if let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") {
        let dir = Path::new(&dir);
        orthomesh::io::write_atomic(
            &dir.join(format!("{name}.vtu")),
            orthomesh::io::vtu::to_string(&h.cells()).as_bytes(),
        )
        .unwrap();
        let tough = orthomesh::io::tough::to_string(&h.mesh.network()).unwrap();
        orthomesh::io::write_atomic(&dir.join(format!("{name}.tough")), tough.as_bytes()).unwrap();
    }
}

/// The 3D hybrid with the defaults but the transition meshed in 3D, sites
/// outside their cells allowed.
pub fn lenient(g: &CornerPointGrid, w: Well3) -> Hybrid3 {
    let b = &compiled()[0];
    let opts = Hybrid3Options {
        allow_sites_outside: true,
        layered: None,
        ..Default::default()
    };
    build(&**b, g, &[w], &opts).unwrap()
}
