//! Fused multiply–adds in the generated kernels, chosen when the program runs.
//!
//! A default build targets the x86-64 baseline, which has no fused multiply–add
//! (`a · b + c` with one rounding). Most processors running it have one (AVX2 and FMA,
//! since 2013). So the derive writes the `f64` forward dynamics and mass matrix twice:
//! the portable function, and a twin compiled with `#[target_feature(enable = "avx2,
//! fma")]` in which each product feeding a sum is fused (`f64::mul_add`) and the joint
//! angles' sines and cosines run four to a register. The kernel calls the twin when
//! [`enabled`] says the processor has both features (detected once, then one relaxed
//! atomic load per call).
//!
//! The kernels generic over their scalar have twins too, which they call on `f64x4`
//! lanes ([`fused_lanes`](super::fused_lanes)); a function too long to be emitted whole
//! has twins of its chunks.
//!
//! The twin rounds differently: its results differ from the portable function's in the
//! last bits (the tests bound by how much). Where runs must agree bit for bit across
//! machines, or with the generic kernels on scalars without twins (`f64`, `f64x2`,
//! `f32`, duals), turn it off with [`set_enabled`]`(false)`.

use std::sync::atomic::{AtomicU8, Ordering};

const UNKNOWN: u8 = 0;
const ON: u8 = 1;
const OFF: u8 = 2;

static STATE: AtomicU8 = AtomicU8::new(UNKNOWN);

/// Whether this processor has AVX2 and FMA (always `false` off x86-64).
pub fn available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether the kernels call their fused twins: [`available`] unless turned off by
/// [`set_enabled`].
#[inline(always)]
pub fn enabled() -> bool {
    match STATE.load(Ordering::Relaxed) {
        ON => true,
        OFF => false,
        _ => detect(),
    }
}

#[cold]
fn detect() -> bool {
    let state = if available() { ON } else { OFF };
    // A `set_enabled` that came first wins.
    match STATE.compare_exchange(UNKNOWN, state, Ordering::Relaxed, Ordering::Relaxed) {
        Ok(_) => state == ON,
        Err(now) => now == ON,
    }
}

/// Turns the fused twins on (where [`available`]) or off for the whole program; returns
/// whether they are now on.
pub fn set_enabled(on: bool) -> bool {
    let on = on && available();
    STATE.store(if on { ON } else { OFF }, Ordering::Relaxed);
    on
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn off_stays_off_and_on_needs_the_processor() {
        assert!(!set_enabled(false));
        assert!(!enabled());
        assert_eq!(set_enabled(true), available());
        assert_eq!(enabled(), available());
    }
}
