//! A fast hasher for the crate's internal hash tables, whose keys are small integers that
//! come from the data itself (never adversarial), where SipHash's cost shows in profiles.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A `HashMap` with [`PointHasher`].
pub(crate) type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<PointHasher>>;

/// A fast multiplicative hasher (FxHash's step) for keys that are small integers and not
/// adversarial: grid points of a DMV, lattice-edge names of a finite element model.
#[derive(Clone, Copy, Default)]
pub struct PointHasher(u64);

impl Hasher for PointHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.write_u64(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut last = [0u8; 8];
            last[..rest.len()].copy_from_slice(rest);
            self.write_u64(u64::from_le_bytes(last));
        }
    }
    #[inline]
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    #[inline]
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    #[inline]
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
}
