//! The particle field for people who look at particles: VTK snapshots for
//! ParaView ([`vtk`]), an SVG picture ([`picture`]), and clean log-axis
//! ticks for the charts ([`ticks`]).

pub mod picture;
pub mod ticks;
pub mod vtk;
