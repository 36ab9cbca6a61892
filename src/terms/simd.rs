//! The instruction set of the packed loops (`terms::lanes` and the regressor kernel),
//! chosen at run time: the widest the CPU has,
//!
//! ```text
//!   AVX-512 (x86-64-v4)   16 lanes = 2 registers of 8     own #[target_feature] function
//!   AVX2 + FMA (v3)       16 lanes = 4 registers of 4     pulp's V3
//!   baseline (SSE2)       16 lanes = 8 registers of 2     no extra feature
//! ```
//!
//! The loops keep 16 accumulators whatever the register width, and every lane does the
//! same operations in the same order (Rust never contracts a · b + c into a fused
//! multiply-add, and the partial sums are added in lane order), so every level gives
//! bitwise the same result: the width changes only how many lanes one instruction
//! advances (tests/simd_levels.rs compares the levels bitwise).
//!
//! AVX-512 is enabled here, for these loops only, rather than through pulp's `x86-v4`
//! feature: faer depends on pulp too, and turning the feature on for pulp would let
//! faer's own dispatch pick AVX-512 kernels, whose reductions round differently, on the
//! machines that have it.
//!
//! [`force`] makes every loop use a lower level (benchmarks, tests); the choice is
//! process-wide.

use std::sync::atomic::{AtomicU8, Ordering};

#[cfg(target_arch = "x86_64")]
use pulp::Simd;

/// An instruction-set level of the packed loops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// AVX-512 F, BW, CD, DQ and VL with AVX2 and FMA (x86-64-v4).
    Avx512,
    /// AVX2 with FMA (x86-64-v3, pulp's `V3`).
    Avx2,
    /// The target's baseline (SSE2 on x86-64), or pulp's own choice off x86-64.
    Baseline,
}

impl Level {
    /// Every level, widest first.
    pub const ALL: [Level; 3] = [Level::Avx512, Level::Avx2, Level::Baseline];

    /// Its name: `avx512`, `avx2` or `baseline`.
    pub fn name(self) -> &'static str {
        match self {
            Level::Avx512 => "avx512",
            Level::Avx2 => "avx2",
            Level::Baseline => "baseline",
        }
    }

    /// Whether this CPU can run the level.
    pub fn available(self) -> bool {
        match self {
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512cd")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512vl")
                    && Level::Avx2.available()
            }
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => pulp::x86::V3::try_new().is_some(),
            #[cfg(not(target_arch = "x86_64"))]
            Level::Avx512 | Level::Avx2 => false,
            Level::Baseline => true,
        }
    }

    /// The widest level this CPU can run.
    pub fn detected() -> Level {
        Level::ALL
            .into_iter()
            .find(|level| level.available())
            .unwrap_or(Level::Baseline)
    }
}

/// 0: not forced; otherwise 1 + the index in [`Level::ALL`] of the forced level.
static FORCED: AtomicU8 = AtomicU8::new(0);

/// The level the loops use now: the forced one ([`force`]), else [`Level::detected`].
pub fn level() -> Level {
    match FORCED.load(Ordering::Relaxed) {
        0 => Level::detected(),
        forced => Level::ALL[usize::from(forced - 1)],
    }
}

/// Makes every packed loop of the process use `level` (`None`: the widest the CPU
/// has again). Returns false, and changes nothing, when the CPU cannot run `level`.
pub fn force(level: Option<Level>) -> bool {
    match level {
        None => FORCED.store(0, Ordering::Relaxed),
        Some(level) if level.available() => {
            let index = Level::ALL.iter().position(|l| *l == level).unwrap_or(0);
            // cannot fail: ALL has three entries, so 1 + index fits a u8.
            FORCED.store(
                u8::try_from(index + 1).expect("three levels"),
                Ordering::Relaxed,
            );
        }
        Some(_) => return false,
    }
    true
}

/// A packed loop with its operands: `run` is marked `#[inline(always)]` so that it
/// compiles inside the target-feature function of each level.
pub(crate) trait Kernel {
    /// What the loop returns.
    type Output;
    /// The loop.
    fn run(self) -> Self::Output;
}

/// Runs `kernel` compiled for [`level`].
#[inline(always)]
pub(crate) fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        match level() {
            // SAFETY: `level` returns Avx512 only when `Level::available` found every
            // feature the function enables.
            Level::Avx512 => unsafe { avx512(kernel) },
            Level::Avx2 => match pulp::x86::V3::try_new() {
                Some(simd) => Simd::vectorize(simd, Pulp(kernel)),
                None => kernel.run(),
            },
            Level::Baseline => kernel.run(),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        pulp::Arch::new().dispatch(Pulp(kernel))
    }
}

/// `kernel` compiled with the features of x86-64-v4.
///
/// # Safety
/// The CPU must have them ([`Level::Avx512`]`.available()`).
#[cfg(target_arch = "x86_64")]
#[target_feature(
    enable = "avx512f,avx512bw,avx512cd,avx512dq,avx512vl,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
)]
unsafe fn avx512<K: Kernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// A kernel handed to pulp's dispatch.
struct Pulp<K>(K);

impl<K: Kernel> pulp::WithSimd for Pulp<K> {
    type Output = K::Output;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> K::Output {
        self.0.run()
    }
}
