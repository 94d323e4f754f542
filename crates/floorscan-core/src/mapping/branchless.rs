//! The per-cell free-space update as conditional moves.
//!
//! Both decisions in it are data: whether a ray already crossed the cell in this scan (true
//! near the sensor, false farther out, mixed in between) and whether the cell sits at the
//! lower clamp (common in well-observed free space). Compiled as branches they mispredict
//! often; LLVM's x86 "cmov conversion" turns the plain Rust selects into branches here because
//! an operand is a load, so on x86-64 the two selects are written as `cmov` directly. Other
//! targets use the plain Rust form. Both forms are checked against each other below.

/// The value of a cell after a free-space observation: `max(value + miss, lower)` if the
/// cell's stamp is not this scan's generation, else `value` unchanged. Requires
/// `value + miss` to fit an i16 (the grid keeps |value| and |miss| <= 16 000).
#[inline(always)]
pub fn free_update(value: i16, stamp: u16, generation: u16, miss: i16, lower: i16) -> i16 {
    let lowered = value.wrapping_add(miss);
    #[cfg(target_arch = "x86_64")]
    {
        let mut out = i32::from(value);
        let candidate = i32::from(lowered);
        // SAFETY: register-only arithmetic (two compares, two conditional moves); no memory
        // access, no stack use. Flags are clobbered, which `asm!` assumes by default.
        unsafe {
            core::arch::asm!(
                "cmp {c:x}, {lo:x}",
                "cmovl {c:e}, {lo:e}",
                "cmp {s:x}, {g:x}",
                "cmovne {o:e}, {c:e}",
                c = inout(reg) candidate => _,
                o = inout(reg) out,
                lo = in(reg) i32::from(lower),
                s = in(reg) u32::from(stamp),
                g = in(reg) u32::from(generation),
                options(pure, nomem, nostack),
            );
        }
        out as i16
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        if stamp != generation {
            lowered.max(lower)
        } else {
            value
        }
    }
}

#[cfg(test)]
#[path = "branchless_tests.rs"]
mod tests;
