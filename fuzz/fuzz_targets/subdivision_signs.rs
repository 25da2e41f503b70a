//! Differential fuzzing: exact vs certified-f64 subdivision sign decisions on small polynomials.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(p) = geocert::internals::fuzzing::decode_poly(data) {
        if let Err(e) = geocert::internals::fuzzing::check_subdivision(&p) {
            panic!("{e}");
        }
    }
});
