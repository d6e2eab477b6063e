//! Fixed-point building blocks under the integer-core routines ([`super::exp`],
//! [`super::atan`], [`super::sqrt_split`]): 16×16 and 32×32 products from
//! the AVR's hardware multiplier, mantissa rounding and packing, shifts by a
//! variable amount that LLVM cannot turn into 255-step loops, and reads of
//! constant tables from flash. One module beneath both exp/ln and atan2, so
//! neither depends on the other.
pub(crate) const MANT_MASK: u32 = 0x007F_FFFF;
pub(crate) const HIDDEN: u32 = 0x0080_0000;

/// a·b for 16-bit a, b. On AVR written out as libgcc's `__umulhisi3` (four
/// 8×8 `mul`s, ~20 cycles): in plain Rust, LLVM fuses the four products of
/// [`mul_full`] back into a 64-bit multiply, a ~700-cycle library call.
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub(crate) fn mul16(a: u16, b: u16) -> u32 {
    u32::from(a) * u32::from(b)
}

#[cfg(target_arch = "avr")]
#[inline(always)]
pub(crate) fn mul16(a: u16, b: u16) -> u32 {
    let lo: u16;
    let hi: u16;
    // SAFETY: register-only arithmetic; `mul` writes r1:r0, and r1 (the
    // zero register) is cleared again before the block ends.
    unsafe {
        core::arch::asm!(
            "mul {a:l}, {b:l}",
            "movw {lo}, r0",
            "mul {a:h}, {b:h}",
            "movw {hi}, r0",
            "mul {a:l}, {b:h}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "eor r1, r1",
            "adc {hi:h}, r1",
            "mul {a:h}, {b:l}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "eor r1, r1",
            "adc {hi:h}, r1",
            a = in(reg_pair) a,
            b = in(reg_pair) b,
            lo = out(reg_pair) lo,
            hi = out(reg_pair) hi,
            options(pure, nomem, nostack),
        );
    }
    (u32::from(hi) << 16) | u32::from(lo)
}

/// The full 64-bit product a·b as (high, low) words, from four 16×16 products
/// (the AVR's hardware multiplier; a `u64` multiply is a slow library call).
#[inline]
pub fn mul_full(a: u32, b: u32) -> (u32, u32) {
    let (a1, a0) = ((a >> 16) as u16, a as u16);
    let (b1, b0) = ((b >> 16) as u16, b as u16);
    let ll = mul16(a0, b0);
    let lh = mul16(a0, b1);
    let hl = mul16(a1, b0);
    let hh = mul16(a1, b1);
    // Each term < 2¹⁶, so the sum < 3·2¹⁶: no overflow.
    let mid = (ll >> 16) + (lh & 0xFFFF) + (hl & 0xFFFF);
    let hi = hh + (lh >> 16) + (hl >> 16) + (mid >> 16);
    let lo = (mid << 16) | (ll & 0xFFFF);
    (hi, lo)
}

/// ⌊a·b / 2³²⌋.
#[inline]
pub fn mul_hi(a: u32, b: u32) -> u32 {
    mul_full(a, b).0
}

/// ⌊a·b / 2³²⌋ or one less: the low×low product is left out (three hardware
/// products instead of four). Enough inside the polynomial, where each step
/// already truncates.
#[cfg(not(target_arch = "avr"))]
#[inline]
pub fn mul_hi_approx(a: u32, b: u32) -> u32 {
    let (a1, a0) = ((a >> 16) as u16, a as u16);
    let (b1, b0) = ((b >> 16) as u16, b as u16);
    let lh = mul16(a0, b1);
    let hl = mul16(a1, b0);
    let hh = mul16(a1, b1);
    let mid = (lh & 0xFFFF) + (hl & 0xFFFF);
    hh + (lh >> 16) + (hl >> 16) + (mid >> 16)
}

/// [`mul_hi_approx`] on the AVR: the same value, ⌊(a₁b₁·2¹⁶ + a₀b₁ + a₁b₀)
/// / 2¹⁶⌋ (16-bit halves), from its twelve 8×8 products summed by column
/// (~64 cycles; LLVM's code for the three 16×16 products and the carries
/// between them took ~80).
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn mul_hi_approx(a: u32, b: u32) -> u32 {
    let (a1, a0) = ((a >> 16) as u16, a as u16);
    let (b1, b0) = ((b >> 16) as u16, b as u16);
    let lo: u16;
    let hi: u16;
    // Bytes: a = A3A2A1A0, b = B3B2B1B0; the sum's bytes 2..5 are the
    // result (p2 = {lo:l} … p5 = {hi:h}); the products in bytes 0..1 of the
    // sum go to l0..l3 first and are added once.
    // SAFETY: register-only arithmetic; `mul` writes r1:r0, and r1 (the
    // zero register) is cleared again before the block ends.
    unsafe {
        core::arch::asm!(
            "mul {a1:l}, {b1:l}",
            "movw {lo}, r0",
            "mul {a1:h}, {b1:h}",
            "movw {hi}, r0",
            "clr {z}",
            // Byte 3: A2B3, A3B2.
            "mul {a1:l}, {b1:h}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "adc {hi:h}, {z}",
            "mul {a1:h}, {b1:l}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "adc {hi:h}, {z}",
            // Byte 2: A1B3, A3B1.
            "mul {a0:h}, {b1:h}",
            "add {lo:l}, r0",
            "adc {lo:h}, r1",
            "adc {hi:l}, {z}",
            "adc {hi:h}, {z}",
            "mul {a1:h}, {b0:h}",
            "add {lo:l}, r0",
            "adc {lo:h}, r1",
            "adc {hi:l}, {z}",
            "adc {hi:h}, {z}",
            // Bytes 0 and 1: A0B2, A2B0; A0B3, A1B2, A2B1, A3B0.
            "mul {a0:l}, {b1:l}",
            "movw {l01}, r0",
            "clr {l2}",
            "clr {l3}",
            "mul {a1:l}, {b0:l}",
            "add {l01:l}, r0",
            "adc {l01:h}, r1",
            "adc {l2}, {z}",
            "mul {a0:l}, {b1:h}",
            "add {l01:h}, r0",
            "adc {l2}, r1",
            "adc {l3}, {z}",
            "mul {a0:h}, {b1:l}",
            "add {l01:h}, r0",
            "adc {l2}, r1",
            "adc {l3}, {z}",
            "mul {a1:l}, {b0:h}",
            "add {l01:h}, r0",
            "adc {l2}, r1",
            "adc {l3}, {z}",
            "mul {a1:h}, {b0:l}",
            "add {l01:h}, r0",
            "adc {l2}, r1",
            "adc {l3}, {z}",
            "add {lo:l}, {l2}",
            "adc {lo:h}, {l3}",
            "adc {hi:l}, {z}",
            "adc {hi:h}, {z}",
            "clr r1",
            a0 = in(reg_pair) a0,
            a1 = in(reg_pair) a1,
            b0 = in(reg_pair) b0,
            b1 = in(reg_pair) b1,
            lo = out(reg_pair) lo,
            hi = out(reg_pair) hi,
            l01 = out(reg_pair) _,
            l2 = out(reg) _,
            l3 = out(reg) _,
            z = out(reg) _,
            options(pure, nomem, nostack),
        );
    }
    (u32::from(hi) << 16) | u32::from(lo)
}

/// Rounds a Q1.31 value in [1, 2)·2³¹ (bit 31 set) to a 24-bit mantissa with
/// its hidden bit; may round up to 2²⁴ (the caller's exponent add carries it).
#[inline(always)]
pub(crate) fn round_mant(m: u32) -> u32 {
    (m >> 8) + ((m >> 7) & 1)
}

/// Packs 2^(e−127)·mant/2²³ for a mantissa from [`round_mant`] and a biased
/// exponent e ≥ 1; a carry out of the mantissa bumps the exponent.
#[inline(always)]
pub(crate) fn pack(sign: u32, biased_exp: u32, mant: u32) -> f32 {
    f32::from_bits(sign | ((biased_exp - 1) << 23).wrapping_add(mant))
}

// Shifts by a variable amount need care on the AVR: LLVM emits a loop of
// one-bit steps (~10 cycles each), and where a shift feeds one arm of an
// `if`, it likes to compute both arms and select, simplifying the amount
// with that arm's conditions first; run for the other arm's inputs, the
// amount has wrapped around and the loop takes 255 steps (seen in
// `expm1_small`: 3 400 cycles in a frame). [`shr`] and [`shl`] take the
// amount through an empty `asm!` block, which LLVM cannot see into, and
// mask it, so any such work stays within 31 steps. Every variable shift in
// the integer cores goes through them.

/// `b` unchanged, but opaque to LLVM (an empty `asm!` block on the AVR):
/// it can no longer reason about the value's range or origin.
#[inline(always)]
pub fn opaque_byte(b: u8) -> u8 {
    #[cfg(target_arch = "avr")]
    {
        let mut b = b;
        // SAFETY: an empty block; `b` stays in its register.
        unsafe { core::arch::asm!("/* {0} */", inout(reg) b, options(pure, nomem, nostack)) };
        b
    }
    #[cfg(not(target_arch = "avr"))]
    {
        b
    }
}

/// A shift amount (< 256) hidden from LLVM's range reasoning.
#[inline(always)]
fn opaque(n: u32) -> u32 {
    u32::from(opaque_byte(n as u8))
}

/// x >> (n mod 32); see the note above.
#[inline(always)]
pub(crate) fn shr(x: u32, n: u32) -> u32 {
    x >> (opaque(n) & 31)
}

/// x << (n mod 32); see the note above.
#[inline(always)]
pub(crate) fn shl(x: u32, n: u32) -> u32 {
    x << (opaque(n) & 31)
}

/// `v.leading_zeros()`, one copy for every caller: LLVM expands the
/// intrinsic inline on the AVR as a 52-instruction bit smear and population
/// count (about 100 bytes at each of ten sites). The top non-zero byte
/// first, then at most seven one-bit steps of that byte.
#[inline(never)] // reason: code-size
pub fn leading_zeros(v: u32) -> u32 {
    let [b3, b2, b1, b0] = v.to_be_bytes();
    let (mut n, mut b) = if b3 != 0 {
        (0u8, b3)
    } else if b2 != 0 {
        (8, b2)
    } else if b1 != 0 {
        (16, b1)
    } else if b0 != 0 {
        (24, b0)
    } else {
        return 32;
    };
    while b & 0x80 == 0 {
        n += 1;
        b <<= 1;
    }
    u32::from(n)
}

/// Reads a u32 from the flash copy of a `.progmem.data` static.
#[cfg(target_arch = "avr")]
#[inline(always)]
pub(crate) fn flash_u32(p: &u32) -> u32 {
    let (b0, b1, b2, b3): (u8, u8, u8, u8);
    // SAFETY: `p` points into a `.progmem.data` static, whose bytes sit in
    // the low 64 KiB of flash (the linker places it at the start of .text),
    // which `lpm` reads; nothing else is touched.
    unsafe {
        core::arch::asm!(
            "lpm {0}, Z+",
            "lpm {1}, Z+",
            "lpm {2}, Z+",
            "lpm {3}, Z+",
            out(reg) b0,
            out(reg) b1,
            out(reg) b2,
            out(reg) b3,
            inout("Z") p as *const u32 as u16 => _,
            options(pure, readonly, nostack),
        );
    }
    u32::from_le_bytes([b0, b1, b2, b3])
}

#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub(crate) fn flash_u32(p: &u32) -> u32 {
    *p
}

#[cfg(test)]
mod tests {
    use super::leading_zeros;

    #[test]
    fn leading_zeros_is_the_intrinsic() {
        assert_eq!(leading_zeros(0), 32);
        for k in 0..32 {
            for v in [1u32 << k, (1u32 << k) - 1, (1u32 << k) | 1, u32::MAX >> k, (1u32 << k).wrapping_mul(0x9E37_79B9)]
            {
                assert_eq!(leading_zeros(v), v.leading_zeros(), "{v:#x}");
            }
        }
        let mut x = 0x1234_5678u32;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            for v in [x, x >> (x % 32)] {
                assert_eq!(leading_zeros(v), v.leading_zeros(), "{v:#x}");
            }
        }
    }
}
