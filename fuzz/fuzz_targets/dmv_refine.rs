//! Differential: random small volumes and LOD sequences; the diamond and supercube fronts give the same conforming mesh.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = geocert::internals::fuzzing::check_dmv_refine(data) {
        panic!("{e}");
    }
});
