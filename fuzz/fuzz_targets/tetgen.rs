//! Any bytes as a TetGen `.poly` or `.smesh`: a 3D complex or a parse
//! error, never a panic; a small complex that validates goes through the
//! whole 3D pipeline on the pure-Rust backend: a certified mesh or an error
//! of the kinds the input can cause.
#![no_main]
use libfuzzer_sys::fuzz_target;
use orthomesh::io::tetgen::{parse, Format};
use orthomesh::{by_name, Error, Mesher, Options};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    for format in [Format::Poly, Format::Smesh] {
        let Ok(cx) = parse(text, Path::new("fuzz.poly"), format) else { continue };
        if cx.validate().is_err() || cx.points.len() > 12 || cx.facets.len() > 12 {
            continue;
        }
        let opts = Options {
            allow_sites_outside: true,
            ..Default::default()
        };
        let pure = by_name("pure").expect("fuzz/ builds the pure-Rust backend");
        match Mesher::new(&*pure).options(opts).conform(&cx) {
            Ok(out) => assert!(out.report.certificate.conforms(), "{:?}", out.report.certificate),
            Err(Error::Backend(m)) => panic!("backend error on valid input: {m}"),
            Err(Error::Internal(m)) => panic!("internal error: {m}"),
            // Known limit (docs/limitations.md): isolated points whose power
            // cells offer too few places for extra sites.
            Err(Error::Certificate(m)) if m.contains("too few places for sites") => {}
            Err(Error::Certificate(m)) if !m.contains("double precision") => panic!("certificate: {m}"),
            Err(_) => {}
        }
    }
});
