//! The allocator of the CLI and the benches (`benches/pipeline.rs` includes
//! this file): mimalloc and its settings. Not in the library: its `override`
//! feature serves malloc for the whole process, which a program linking the
//! crate must choose itself.

/// mimalloc for every allocation, HiGHS' C++ ones too (its `override`
/// feature): the local form's thousands of small LP solves allocate and
/// free per solve (measured: 7% of a 10^5-segment run). Without
/// transparent huge pages (its `no_thp` feature): memory it returns and
/// takes again was zeroed 2 MiB at a time (measured: 15% of a 10^5-segment
/// run's CPU time in the kernel's page clearing, 1% without).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// mimalloc's option `mi_option_purge_delay` (its number in the v3
/// `mi_option_e`, which libmimalloc-sys 0.1.49 builds; the crate's bindings
/// lack the constant).
const PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// Keeps the memory mimalloc frees for its next allocations instead of
/// returning it to the system (by default a second after it is freed).
/// The stages free large arrays and allocate new ones, and every page taken
/// back from the system costs a page fault and its zeroing: measured, 5-8%
/// of a 10^5-segment field's pipeline, for a peak 16% higher there (3% on
/// SPE9 in 3D); the process holds that memory until it ends.
#[allow(unsafe_code)]
pub fn keep_freed_memory() {
    // SAFETY: sets an integer option; mimalloc reads options atomically.
    unsafe { libmimalloc_sys::mi_option_set(PURGE_DELAY, -1) }
}

#[cfg(test)]
mod tests {
    /// Option 15 is the purge delay: v3's default of 1000 ms (unless the
    /// environment sets it).
    #[test]
    #[allow(unsafe_code)]
    fn option_15_is_the_purge_delay() {
        if std::env::var_os("MIMALLOC_PURGE_DELAY").is_some() {
            return;
        }
        // SAFETY: reads an integer option.
        let before = unsafe { libmimalloc_sys::mi_option_get(super::PURGE_DELAY) };
        assert_eq!(before, 1000);
    }
}
