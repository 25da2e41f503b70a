//! Robustness: the .dmv reader on arbitrary bytes never panics; what it accepts writes back canonically and refines to a conforming mesh.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = geocert::internals::fuzzing::check_dmv_file(data) {
        panic!("{e}");
    }
});
