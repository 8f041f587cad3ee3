//! Any bytes as a Triangle .poly: a complex or a parse error, never a panic;
//! a complex that validates writes and reads back unchanged.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(cx) = orthomesh::io::poly::parse(text, Path::new("fuzz.poly")) {
        if cx.validate().is_ok() {
            let back = orthomesh::io::poly::parse(&orthomesh::io::poly::to_string(&cx), Path::new("back.poly"))
                .expect("written .poly reads back");
            assert_eq!(back.points, cx.points);
            assert_eq!(back.segments, cx.segments);
        }
    }
});
