//! The particle field for people who look at particles: VTK snapshots for
//! ParaView ([`vtk`]), a run's series and picture ([`series`]), and the SVG
//! picture ([`picture`]).

pub mod picture;
pub mod series;
pub mod vtk;
