//! Instruction-set dispatch: the vector instructions the pair loops are
//! compiled for, chosen at run time, and the lane helpers every pass shares.

use crate::solver::neighbours::LANES;

/// Entries a pair loop takes at a time, in buffers on the stack (a whole
/// number of lane groups; a list longer than this takes several). The
/// kernel pass runs its distance, kernel and store loops block by block:
/// 128 pairs rather than 64 ran the PySPH scene 1.07x faster on one thread
/// on a Zen 3 (7 alternating rounds; 256 and 512 no faster again), morris
/// 1.04-1.07x at every size of `bench` on one thread, the kernel loop's
/// long latency chain (square root, division, two Horner sums) paid for
/// over twice as many vectors; wendland_c2 3.6 % slower at 1e5-1e6
/// particles, the rest within the noise (measured with `shearsph bench`). The same
/// bits: each pair's operations do not depend on where a block ends.
pub(super) const BLOCK: usize = 16 * LANES;

/// Two buffers of a block's entries, made once per parallel task (zeroing
/// them per particle would cost more than some particles' pairs).
pub(super) type Scratch = ([f64; BLOCK], [f64; BLOCK]);

/// The pairwise sum of the lane accumulators, in a fixed order.
#[inline(always)]
pub(super) fn lane_sum(a: [f64; LANES]) -> f64 {
    ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
}

/// The vector instructions the pair loops are compiled for, chosen at run
/// time. Each is the same source, the same operations in the same order:
/// the results are the same bits on every CPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Isa {
    #[cfg(target_arch = "x86_64")]
    Avx512,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    Base,
}

/// Every instruction set this CPU runs (the baseline, the one detected,
/// and AVX2 under AVX-512), for the tests that compare their bits.
#[cfg(test)]
pub(crate) fn every_isa() -> Vec<Isa> {
    let mut isas = vec![Isa::Base, Isa::detect()];
    #[cfg(target_arch = "x86_64")]
    if Isa::detect() == Isa::Avx512 {
        isas.push(Isa::Avx2);
    }
    isas
}

impl Isa {
    /// Name and f64 lanes per vector register.
    pub(crate) fn describe(self) -> (&'static str, u32) {
        match self {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => ("AVX-512", 8),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => ("AVX2", 4),
            Isa::Base => ("baseline (SSE2 on x86-64)", 2),
        }
    }

    pub(crate) fn detect() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("avx512vl")
            {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Isa::Avx2;
            }
        }
        Isa::Base
    }
}
