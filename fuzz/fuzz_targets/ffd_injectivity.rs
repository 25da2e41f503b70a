//! Differential: exact vs fast vs filtered N&S injectivity on small lattices (orders 2–4,
//! 1–2 cells per axis, bounded perturbations of the identity).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(l) = geocert::internals::fuzzing::decode_lattice(data) {
        if let Err(msg) = geocert::internals::fuzzing::check_ffd(&l) {
            panic!("{msg}");
        }
    }
});
