//! Robustness: the PLY, OBJ and STL readers on arbitrary bytes never panic, and what they
//! accept round-trips.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(msg) = geocert::internals::fuzzing::check_mesh_readers(data) {
        panic!("{msg}");
    }
});
