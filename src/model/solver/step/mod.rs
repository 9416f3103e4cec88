//! The particle state (structure of arrays) and the passes of one step, one
//! file per phase: [`state`] (particles and the per-step constants),
//! [`integrate`] (kick-drift), [`density`] (summation and EOS), [`forces`]
//! (accelerations and the closing kick), [`isa`] (the instruction set the
//! pair loops run with). Each pass reads the neighbour list (the force pass
//! its windows), parallel over fixed chunks of particles; a particle's sums
//! run in its list's order, so results do not depend on the thread count.

/// Defines `$on(isa, args..)`: `$inner(args..)` compiled for the instruction
/// set `isa` (AVX-512, AVX2 or the baseline), each a `#[target_feature]`
/// copy of the same `#[inline(always)]` body, so the results are the same
/// bits on every CPU. One of the two places the passes meet `unsafe`:
/// calling a target-feature function is sound because [`Isa::detect`] found
/// the features before any `Isa` other than `Base` exists. (The other: the
/// kernel pass views its window-lane table as atomics, `density::as_atomic`,
/// so that its tasks can store into it at once.)
macro_rules! on_isa {
    (
        $(#[$attr:meta])*
        $vis:vis fn $on:ident [$($gen:tt)*] => $inner:ident [$($targs:tt)*]
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?
    ) => {
        $(#[$attr])*
        #[inline(always)]
        $vis fn $on<$($gen)*>(isa: $crate::solver::step::Isa, $($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
            unsafe fn avx512<$($gen)*>($($arg: $ty),*) $(-> $ret)? {
                $inner::<$($targs)*>($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2")]
            unsafe fn avx2<$($gen)*>($($arg: $ty),*) $(-> $ret)? {
                $inner::<$($targs)*>($($arg),*)
            }
            match isa {
                // SAFETY: an `Isa` other than `Base` comes only from
                // `Isa::detect`, which found the CPU features.
                #[cfg(target_arch = "x86_64")]
                $crate::solver::step::Isa::Avx512 => unsafe { avx512::<$($targs)*>($($arg),*) },
                #[cfg(target_arch = "x86_64")]
                $crate::solver::step::Isa::Avx2 => unsafe { avx2::<$($targs)*>($($arg),*) },
                $crate::solver::step::Isa::Base => $inner::<$($targs)*>($($arg),*),
            }
        }
    };
}

mod density;
mod forces;
mod integrate;
mod isa;
mod state;

pub(crate) use density::{
    density, density_sums, kernel_alone_ns, kernel_pass, DENSITY_DISTANCE_FLOPS, DENSITY_SUM_FLOPS,
};
pub(crate) use forces::{
    forces, Forces, FORCE_PAIR_FLOPS, FORCE_PAIR_FLOPS_AV, FORCE_PAIR_FLOPS_MIRROR,
};
pub(crate) use integrate::kick_drift;
pub(crate) use isa::Isa;
pub(crate) use state::{Params, State};

/// Particles per parallel task: large enough that a task outweighs rayon's
/// overhead on the small scenes this problem needs.
pub(super) const CHUNK: usize = 128;
