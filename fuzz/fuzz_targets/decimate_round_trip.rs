//! Decimation round trip on arbitrary small meshes (height grids and arbitrary triangles):
//! an error or a run that passes the exact checker and undecimates bit for bit; the history
//! parser on arbitrary bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(msg) = geocert::internals::fuzzing::check_decimate(data) {
        panic!("{msg}");
    }
});
