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

/// Calls of a pass that a pick's trial takes, its candidates in turn, and
/// the calls after which it tries again ([`Pick`]).
pub(crate) const TRIAL: u32 = 16;
const PERIOD: u32 = 4096;

/// One of two forms of a pass (an instruction set, [`IsaPick`]; where the
/// kernel pass leaves (dW/dq)/q, [`super::GForm`]), picked by what it
/// cost. Every candidate gives the same bits, so the pick changes only the
/// speed. Every PERIOD calls, the TRIAL calls from the pick's `offset`
/// take the candidates in turn, and the one whose quickest call was the
/// quicker runs the rest: the quickest, not the total, as a call right
/// after a rebuild also zeroes its tables. Picks of passes timed in the
/// same steps take their trials at different offsets, so that no trial's
/// candidates alternate in step with another's.
#[derive(Debug, Clone)]
pub(crate) struct Pick<T> {
    candidates: [T; 2],
    quickest: [f64; 2],
    calls: u32,
    offset: u32,
    chosen: T,
}

/// The instruction set one pair pass of the step runs with (the pass's
/// functions are the same operations in the same order on every set,
/// which the tests compare: the same bits). The candidates are the set
/// detected and, under AVX-512, AVX2: a CPU that runs 512-bit vectors as
/// two halves (AMD's Zen 4) runs a pass whose vectors are mostly gathers
/// faster with 256-bit ones, and one of arithmetic slower
/// (docs/performance.md).
pub(crate) type IsaPick = Pick<Isa>;

impl Pick<Isa> {
    /// Between the set detected and, under AVX-512, AVX2.
    pub(crate) fn new() -> IsaPick {
        let detected = Isa::detect();
        #[cfg(target_arch = "x86_64")]
        let other = if detected == Isa::Avx512 {
            Isa::Avx2
        } else {
            detected
        };
        #[cfg(not(target_arch = "x86_64"))]
        let other = detected;
        Pick::between([detected, other], 0)
    }
}

impl<T: Copy> Pick<T> {
    /// Always `form` (for the tests that compare forms).
    #[cfg(test)]
    pub(crate) fn fixed(form: T) -> Pick<T> {
        Pick::between([form, form], 0)
    }

    /// Between `candidates`, the first until the first trial, which takes
    /// the calls from `offset` (below PERIOD - TRIAL).
    pub(crate) fn between(candidates: [T; 2], offset: u32) -> Pick<T> {
        assert!(offset + TRIAL <= PERIOD);
        Pick {
            candidates,
            quickest: [f64::INFINITY; 2],
            calls: 0,
            offset,
            chosen: candidates[0],
        }
    }

    /// The call's place in the trial, if it is in one.
    fn in_trial(&self) -> Option<u32> {
        let k = self.calls.checked_sub(self.offset)?;
        (k < TRIAL).then_some(k)
    }

    /// Whether the next call is one of a trial's.
    pub(crate) fn trying(&self) -> bool {
        self.in_trial().is_some()
    }

    /// The form for the next call.
    pub(crate) fn next(&self) -> T {
        match self.in_trial() {
            Some(k) => self.candidates[(k % 2) as usize],
            None => self.chosen,
        }
    }

    /// The seconds the call with [`Self::next`] took.
    pub(crate) fn record(&mut self, seconds: f64) {
        self.count(Some(seconds));
    }

    /// A call that took neither candidate (the pass had one form then):
    /// counted, so that the trials keep their place among the calls, and
    /// not measured. A trial without a measure of each candidate keeps the
    /// choice it found.
    pub(crate) fn skip(&mut self) {
        self.count(None);
    }

    fn count(&mut self, seconds: Option<f64>) {
        if let Some(k) = self.in_trial() {
            if let Some(seconds) = seconds {
                let q = &mut self.quickest[(k % 2) as usize];
                *q = q.min(seconds);
            }
            if k + 1 == TRIAL && self.quickest.iter().all(|q| q.is_finite()) {
                let c = usize::from(self.quickest[1] < self.quickest[0]);
                self.chosen = self.candidates[c];
            }
        }
        self.calls += 1;
        if self.calls == PERIOD {
            self.calls = 0;
            self.quickest = [f64::INFINITY; 2];
        }
    }

    /// The form the calls after the last trial run with.
    pub(crate) fn chosen(&self) -> T {
        self.chosen
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pick runs its candidates in turn for TRIAL calls, then the one
    /// whose quickest call was the quicker (one slow call, as after a
    /// rebuild, does not decide it), and tries again every PERIOD calls.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn a_pick_takes_the_quicker_set_and_tries_again() {
        let mut pick = IsaPick::between([Isa::Avx512, Isa::Avx2], 0);
        // AVX2 quicker, but for one slow call.
        let cost = |isa: Isa, call: u32| match isa {
            Isa::Avx512 => 1.0,
            _ if call == 1 => 5.0,
            _ => 0.8,
        };
        for call in 0..TRIAL {
            let isa = pick.next();
            assert_eq!(isa, [Isa::Avx512, Isa::Avx2][(call % 2) as usize]);
            pick.record(cost(isa, call));
        }
        assert_eq!(pick.chosen(), Isa::Avx2);
        for _ in TRIAL..PERIOD {
            assert_eq!(pick.next(), Isa::Avx2);
            pick.record(0.8);
        }
        // The next trial, where AVX-512 is now the quicker.
        for call in 0..TRIAL {
            let isa = pick.next();
            assert_eq!(isa, [Isa::Avx512, Isa::Avx2][(call % 2) as usize]);
            pick.record(if isa == Isa::Avx512 { 0.5 } else { 0.8 });
        }
        assert_eq!((pick.next(), pick.chosen()), (Isa::Avx512, Isa::Avx512));
    }

    /// A pick with an offset runs its first candidate until its trial,
    /// which takes the TRIAL calls from the offset, every PERIOD calls.
    #[test]
    fn a_pick_with_an_offset_tries_after_it() {
        let mut pick = Pick::between([true, false], TRIAL);
        let cost = |form: bool| if form { 1.0 } else { 0.5 };
        for round in 0..2 {
            for call in 0..PERIOD {
                let form = pick.next();
                let trial = (TRIAL..2 * TRIAL).contains(&call);
                let want = if trial {
                    (call - TRIAL).is_multiple_of(2)
                } else {
                    // The first candidate until the first trial.
                    round == 0 && call < TRIAL
                };
                assert_eq!(form, want, "round {round}, call {call}");
                pick.record(cost(form));
            }
        }
    }

    /// Calls that took neither candidate count but measure nothing: a
    /// trial of such calls keeps the choice, and the next trial falls
    /// where it would have.
    #[test]
    fn a_skipped_trial_keeps_the_choice() {
        let mut pick = Pick::between([true, false], TRIAL);
        for _ in 0..PERIOD {
            let form = pick.next();
            pick.record(if form { 1.0 } else { 0.5 });
        }
        assert!(!pick.chosen());
        for _ in 0..PERIOD {
            pick.skip();
        }
        assert!(!pick.chosen(), "no measure, no new choice");
        for call in 0..2 * TRIAL {
            assert_eq!(pick.trying(), call >= TRIAL, "call {call}");
            let form = pick.next();
            pick.record(if form { 0.5 } else { 1.0 });
        }
        assert!(pick.chosen(), "measured again, the other");
    }
}
