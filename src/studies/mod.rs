//! The studies: what asks the model questions by running it. One scene by
//! kernel name ([`run`], the visitor every study goes through), the
//! empirical answer ([`empirical`]), the law over N x Re x alpha ([`law`]),
//! grids of scenes ([`sweep`]), the report ([`report`]), the lattice's
//! linear stability ([`stability`]) and the solver's cost ([`bench`]).
//! They read the model and write through [`crate::io`]; the crate root
//! re-exports each module (`crate::sweep` is `crate::studies::sweep`).

pub mod bench;
pub mod empirical;
pub mod law;
pub mod report;
pub mod run;
pub mod stability;
pub mod sweep;
