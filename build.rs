//! Compiles the CGAL shim (feature `cgal`). Fails with guidance, not a panic
//! trace, when CGAL or GMP is missing.

fn main() {
    #[cfg(feature = "cgal")]
    cgal::build();
}

#[cfg(feature = "cgal")]
mod cgal {
    use std::path::Path;

    const HELP: &str = "install the system packages with `bash scripts/setup.sh` \
        (libcgal-dev, libgmp-dev, libmpfr-dev), or build without the CGAL backend";

    pub fn build() {
        let cgal_dir = std::env::var("CGAL_INCLUDE_DIR").unwrap_or_else(|_| "/usr/include".into());
        if !Path::new(&cgal_dir)
            .join("CGAL/Regular_triangulation_2.h")
            .exists()
        {
            println!("cargo:warning=CGAL headers not found under {cgal_dir}: {HELP}");
            eprintln!(
                "error: CGAL headers not found under {cgal_dir} (set CGAL_INCLUDE_DIR): {HELP}"
            );
            std::process::exit(1);
        }
        if !Path::new("/usr/include/gmp.h").exists()
            && !Path::new("/usr/include/x86_64-linux-gnu/gmp.h").exists()
        {
            println!("cargo:warning=gmp.h not found: {HELP}");
        }
        cxx_build::bridge("src/backend/cgal/ffi.rs")
            .files([
                "cpp/regular2.cpp",
                "cpp/regular2_exact.cpp",
                "cpp/regular3.cpp",
                "cpp/regular3_exact.cpp",
            ])
            .include(&cgal_dir)
            .std("c++17")
            // Unoptimised CGAL is ~24x slower; rounding-math keeps the interval
            // filters of the exact kernels sound.
            .opt_level(2)
            .flag_if_supported("-frounding-math")
            .flag_if_supported("-Wno-deprecated-declarations")
            .flag_if_supported("-Wno-maybe-uninitialized")
            .define("CGAL_NDEBUG", None)
            .compile("orthomesh_cgal");
        println!("cargo:rustc-link-lib=gmp");
        println!("cargo:rustc-link-lib=mpfr");
        for f in [
            "cpp/shim.h",
            "cpp/collect.h",
            "cpp/regular2.cpp",
            "cpp/regular2_exact.cpp",
            "cpp/hidden.h",
            "cpp/regular3.h",
            "cpp/regular3.cpp",
            "cpp/regular3_exact.cpp",
            "src/backend/cgal/ffi.rs",
        ] {
            println!("cargo:rerun-if-changed={f}");
        }
        println!("cargo:rerun-if-env-changed=CGAL_INCLUDE_DIR");
    }
}
