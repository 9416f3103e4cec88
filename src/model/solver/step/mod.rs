//! The particle state (structure of arrays) and the passes of one step, one
//! file per phase: [`state`] (particles and the per-step constants),
//! [`integrate`] (kick-drift), [`density`] (summation and EOS), [`forces`]
//! (accelerations and the closing kick), [`isa`] (the instruction set the
//! pair loops run with). Each pass reads the neighbour list (the force pass
//! its windows), parallel over fixed chunks of particles; a particle's sums
//! run in its list's order, so results do not depend on the thread count.

mod density;
mod forces;
mod integrate;
mod isa;
mod state;

pub(crate) use density::{
    density, density_sums, kernel_alone_ns, kernel_pass, GForm, DENSITY_DISTANCE_FLOPS,
    DENSITY_SUM_FLOPS,
};
pub(crate) use forces::{
    forces, forces_in_tiles, Forces, FORCE_PAIR_FLOPS, FORCE_PAIR_FLOPS_AV,
    FORCE_PAIR_FLOPS_MIRROR, FORCE_TILE,
};
pub(crate) use integrate::kick_drift;
#[cfg(test)]
pub(crate) use isa::every_isa;
pub(crate) use isa::{Isa, IsaPick, Pick, TRIAL as PICK_TRIAL};
#[cfg(test)]
pub(crate) use state::blocks_rotated;
pub(crate) use state::{Params, State};

/// Particles per parallel task: large enough that a task outweighs rayon's
/// overhead on the small scenes this problem needs.
pub(super) const CHUNK: usize = 128;
