//! The particle field for people who look at particles: VTK snapshots for
//! ParaView ([`vtk`]), a run's series and picture ([`series`]), an SVG
//! picture ([`picture`]), and clean log-axis ticks for the charts
//! ([`ticks`]).

pub mod picture;
pub mod series;
pub mod ticks;
pub mod vtk;
