//! Any bytes as an Eclipse GRDECL file (and as a deck for wells): a grid or
//! an error, never a panic or an allocation the header asks for blindly.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The readers take paths (INCLUDE is relative to the file).
    let dir = std::env::temp_dir().join(format!("orthomesh-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("fuzz.grdecl");
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let _ = orthomesh::io::eclipse::read_grid(&path);
    let _ = orthomesh::io::eclipse::read_wells(&path);
});
