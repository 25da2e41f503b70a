//! Robustness: the lattice JSON reader on arbitrary bytes never panics and round-trips.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(msg) = geocert::internals::fuzzing::check_lattice_json(data) {
        panic!("{msg}");
    }
});
