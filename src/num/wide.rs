//! A 256-bit signed accumulator for exact integer convolutions whose operands fit `i128`:
//! products of two `i128` are formed exactly (four 64×64-bit partial products) and summed with
//! overflow checks. Used by the sign-only integer kernel before falling back to `BigInt`.

use num_bigint::BigInt;

/// `hi · 2¹²⁸ + lo`, two's complement over 256 bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct I256 {
    hi: i128,
    lo: u128,
}

/// The exact 256-bit product of two 128-bit unsigned values as `(hi, lo)`.
fn mul_u128(a: u128, b: u128) -> (u128, u128) {
    let (a1, a0) = (a >> 64, a & u64::MAX as u128);
    let (b1, b0) = (b >> 64, b & u64::MAX as u128);
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    // Middle column: p01 + p10 + (p00 >> 64), may exceed 128 bits by one carry.
    let (mid, c1) = p01.overflowing_add(p10);
    let (mid, c2) = mid.overflowing_add(p00 >> 64);
    let carry = (c1 as u128 + c2 as u128) << 64;
    let lo = (mid << 64) | (p00 & u64::MAX as u128);
    let hi = p11 + (mid >> 64) + carry;
    (hi, lo)
}

impl I256 {
    pub(crate) const ZERO: I256 = I256 { hi: 0, lo: 0 };

    /// The exact product `a · b`.
    pub(crate) fn product(a: i128, b: i128) -> I256 {
        let neg = (a < 0) != (b < 0);
        let (hi, lo) = mul_u128(a.unsigned_abs(), b.unsigned_abs());
        // |a|,|b| ≤ 2¹²⁷ so |a·b| ≤ 2²⁵⁴ and `hi` < 2¹²⁷ fits the signed high half.
        let v = I256 { hi: hi as i128, lo };
        if neg {
            v.negate()
        } else {
            v
        }
    }

    fn negate(self) -> I256 {
        // Two's complement: invert and add one.
        let lo = (!self.lo).wrapping_add(1);
        let hi = (!self.hi).wrapping_add(if lo == 0 { 1 } else { 0 });
        I256 { hi, lo }
    }

    /// `self + o`, or `None` on overflow of 256 bits.
    pub(crate) fn checked_add(self, o: I256) -> Option<I256> {
        let (lo, carry) = self.lo.overflowing_add(o.lo);
        let hi = self.hi.checked_add(o.hi)?.checked_add(carry as i128)?;
        Some(I256 { hi, lo })
    }

    /// `self · 2⁶⁴`, or `None` on overflow of 256 bits.
    pub(crate) fn checked_shl64(self) -> Option<I256> {
        let top = self.hi >> 63; // must be all sign bits above bit 191
        if top != 0 && top != -1 {
            return None;
        }
        let hi = (self.hi << 64) | (self.lo >> 64) as i128;
        Some(I256 {
            hi,
            lo: self.lo << 64,
        })
    }

    /// `a · 2⁶⁴ + b` times `y` exactly for `a, y` in `i128` and `0 ≤ b < 2⁶⁴`, or `None`.
    pub(crate) fn split_product(a: i128, b: u64, y: i128) -> Option<I256> {
        I256::product(a, y)
            .checked_shl64()?
            .checked_add(I256::product(b as i128, y))
    }

    pub(crate) fn to_bigint(self) -> BigInt {
        // The common case fits `i128`: the high half is only sign bits of the low one.
        let low = self.lo as i128;
        if self.hi == low >> 127 {
            return BigInt::from(low);
        }
        (BigInt::from(self.hi) << 128) + BigInt::from(self.lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_products_match_bigint() {
        for (a, b, y) in [
            (3i128, 5u64, 7i128),
            (-(1 << 100), u64::MAX, (1 << 80) - 3),
            ((1 << 120) + 1, 12345, -(1 << 60)),
            (-1, 0, i128::MAX),
        ] {
            let exact = ((BigInt::from(a) << 64) + BigInt::from(b)) * BigInt::from(y);
            match I256::split_product(a, b, y) {
                Some(v) => assert_eq!(v.to_bigint(), exact),
                None => assert!(exact.bits() > 250),
            }
        }
    }

    #[test]
    fn products_and_sums_match_bigint() {
        let vals: [i128; 9] = [
            0,
            1,
            -1,
            i128::MAX,
            i128::MIN + 1,
            (1 << 100) + 12345,
            -(1 << 90) - 7,
            0x1234_5678_9abc_def0_1234_5678,
            -0x0fed_cba9_8765_4321_0fed,
        ];
        let mut acc = I256::ZERO;
        let mut big = BigInt::from(0);
        for &a in &vals {
            for &b in &vals {
                let p = I256::product(a, b);
                assert_eq!(
                    p.to_bigint(),
                    BigInt::from(a) * BigInt::from(b),
                    "{a} * {b}"
                );
                if let Some(s) = acc.checked_add(p) {
                    acc = s;
                    big += BigInt::from(a) * BigInt::from(b);
                    assert_eq!(acc.to_bigint(), big);
                }
            }
        }
    }
}
