//! Any bytes as a CGAL .edg segment soup: a complex or a parse error, and
//! validation gives a verdict; never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(cx) = orthomesh::io::edg::parse(text, Path::new("fuzz.edg")) {
        let _ = cx.validate();
    }
});
