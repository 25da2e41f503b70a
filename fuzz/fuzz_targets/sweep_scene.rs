//! Robustness: the swept-scene reader and the silhouette equations on arbitrary bytes never
//! panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = geocert::internals::fuzzing::check_sweep_scene(data);
});
