//! See `geocert::internals::fuzzing::check_mc_verify`.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(msg) = geocert::internals::fuzzing::check_mc_verify(data) {
        panic!("{msg}");
    }
});
