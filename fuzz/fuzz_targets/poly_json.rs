//! Robustness: the polynomial JSON reader on arbitrary bytes never panics.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = geocert::internals::fuzzing::check_poly_json(data);
});
