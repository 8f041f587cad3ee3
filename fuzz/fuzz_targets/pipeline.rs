//! Any bytes as a small complex (points on a fine lattice, segments between
//! them) through the whole pipeline on the pure-Rust backend: a certified
//! mesh or an error of the kinds the input can cause; never a panic, never
//! an uncertified mesh.
#![no_main]
use libfuzzer_sys::fuzz_target;
use orthomesh::{by_name, Complex, Error, Mesher, Options};

fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let np = (data[0] as usize % 12) + 3;
    let (head, rest) = data[1..].split_at((2 * np).min(data.len() - 1));
    let points: Vec<[f64; 2]> = head
        .chunks_exact(2)
        .map(|c| [c[0] as f64 / 16.0, c[1] as f64 / 16.0])
        .collect();
    let n = points.len() as u32;
    if n < 3 {
        return;
    }
    let segments = rest
        .chunks_exact(2)
        .take(16)
        .map(|c| [c[0] as u32 % n, c[1] as u32 % n])
        .collect();
    let cx = Complex::new(points, segments);
    let opts = Options {
        allow_sites_outside: true,
        ..Default::default()
    };
    let pure = by_name("pure").expect("fuzz/ builds the pure-Rust backend");
    match Mesher::new(&*pure).options(opts).conform(&cx) {
        Ok(out) => assert!(out.report.certificate.conforms(), "{:?}", out.report.certificate),
        Err(Error::Backend(m)) => panic!("backend error on valid input: {m}"),
        Err(Error::Internal(m)) => panic!("internal error: {m}"),
        Err(Error::Certificate(m)) if !m.contains("double precision") => panic!("certificate: {m}"),
        Err(_) => {}
    }
});
