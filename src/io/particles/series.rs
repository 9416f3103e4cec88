//! A run's particle output: [`ParticleOutput`] wraps any observer, writes
//! every K-th output time's particle field as `particles_NNNNN.vtu` and
//! `particles.pvd` ([`super::vtk`]) and keeps the last field it saw; after
//! the run [`ParticleOutput::finish`] writes that last field too (the end,
//! the failure or the stop, if the stride skipped it) and
//! [`write_picture`] draws it as `particles.svg`, the failing particle
//! ringed.

use std::path::Path;

use anyhow::Result;

use super::picture::{particle_svg, ColourBy, Mark};
use super::vtk::{ParticleFrame, SeriesWriter};
use crate::output::write_atomic;
use crate::solver::{Observer, Outcome, RunResult, Sample};

/// The `.pvd` (and `.vtu` prefix) a run writes.
pub const STEM: &str = "particles";
/// The picture beside the profile chart.
pub const PICTURE: &str = "particles.svg";
/// Bytes of one `.vtu` per particle, measured (`tests/particles_vtk.rs`):
/// the pre-run size estimate.
pub const VTU_BYTES_PER_PARTICLE: f64 = 125.0;

/// A particle field owned (the last one seen, kept for the picture).
#[derive(Debug, Clone, Default)]
pub struct Snapshot {
    pub time: f64,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    pub density: Vec<f64>,
    pub pressure: Vec<f64>,
    pub eps: Vec<f64>,
    pub wall: Vec<bool>,
    pub layer: Vec<i32>,
}

impl Snapshot {
    /// Copy `f` in, reusing the buffers.
    pub fn copy_from(&mut self, f: &ParticleFrame) {
        fn put<T: Copy>(to: &mut Vec<T>, from: &[T]) {
            to.clear();
            to.extend_from_slice(from);
        }
        self.time = f.time;
        put(&mut self.x, f.x);
        put(&mut self.y, f.y);
        put(&mut self.vx, f.vx);
        put(&mut self.vy, f.vy);
        put(&mut self.density, f.density);
        put(&mut self.pressure, f.pressure);
        put(&mut self.eps, f.eps);
        put(&mut self.wall, f.wall);
        put(&mut self.layer, f.layer);
    }

    pub fn frame(&self) -> ParticleFrame<'_> {
        ParticleFrame {
            time: self.time,
            x: &self.x,
            y: &self.y,
            vx: &self.vx,
            vy: &self.vy,
            density: &self.density,
            pressure: &self.pressure,
            eps: &self.eps,
            wall: &self.wall,
            layer: &self.layer,
        }
    }
}

/// An observer that adds particle output to `inner` (which sees everything
/// else unchanged).
pub struct ParticleOutput<'a> {
    inner: &'a mut dyn Observer,
    /// Writes every `every`-th output (from the first, t = 0); `None`:
    /// keeps the last field only (for the picture).
    writer: Option<(SeriesWriter, u64)>,
    seen: u64,
    last: Option<Snapshot>,
    /// Whether `last` is in the series already.
    last_written: bool,
    error: Option<anyhow::Error>,
}

impl<'a> ParticleOutput<'a> {
    /// Writes the series into `dir` at every `every`-th output time when
    /// `every` is `Some` (K >= 1), and keeps the last field either way.
    pub fn new(inner: &'a mut dyn Observer, dir: &Path, every: Option<u64>) -> Self {
        ParticleOutput {
            inner,
            writer: every.map(|k| (SeriesWriter::new(dir, STEM), k.max(1))),
            seen: 0,
            last: None,
            last_written: false,
            error: None,
        }
    }

    /// After the run: writes the last field if the stride skipped it (so the
    /// series ends where the run ended), and gives the first write error.
    /// Returns the last field.
    pub fn finish(mut self) -> Result<Option<Snapshot>> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        if let (Some((w, _)), Some(last)) = (self.writer.as_mut(), self.last.as_ref()) {
            if !self.last_written {
                w.write(&last.frame())?;
            }
        }
        Ok(self.last)
    }
}

impl Observer for ParticleOutput<'_> {
    fn step(&mut self, t: f64, steps: u64) {
        self.inner.step(t, steps);
    }
    fn output(&mut self, sample: &Sample) {
        self.inner.output(sample);
    }
    fn should_stop(&self) -> bool {
        self.inner.should_stop()
    }
    fn wants_particles(&self) -> bool {
        true
    }
    fn particles(&mut self, frame: &ParticleFrame) {
        let k = self.seen;
        self.seen += 1;
        self.last
            .get_or_insert_with(Snapshot::default)
            .copy_from(frame);
        self.last_written = false;
        if self.error.is_some() {
            return;
        }
        if let Some((w, every)) = self.writer.as_mut() {
            if k.is_multiple_of(*every) {
                match w.write(frame) {
                    Ok(_) => self.last_written = true,
                    Err(e) => self.error = Some(e),
                }
            }
        }
    }
}

/// The mark for a failed run: its failing particle, labelled with why.
pub fn failure_mark(result: &RunResult) -> Option<Mark> {
    match &result.outcome {
        Outcome::Failed {
            failure, particle, ..
        } => Some(Mark {
            index: particle.index,
            label: format!("particle {} ({})", particle.index, failure.kind().name()),
        }),
        _ => None,
    }
}

/// The picture of `last` (coloured by eps, the failing particle ringed on
/// a failed run) as SVG.
pub fn picture_svg(last: &Snapshot, result: &RunResult) -> Result<String> {
    let mark = failure_mark(result);
    let title = format!(
        "{} N = {}, c0 / U = {}: particles at t = {:.4} ({})",
        result.kernel,
        result.problem.lattice.n_layers,
        crate::format::fmt_num(result.problem.c0 / result.problem.flow.u),
        last.time,
        result.outcome.status()
    );
    particle_svg(&last.frame(), ColourBy::Eps, mark.as_ref(), &title)
}

/// Writes [`picture_svg`] as `dir/particles.svg`, atomically.
pub fn write_picture(dir: &Path, last: &Snapshot, result: &RunResult) -> Result<()> {
    write_atomic(&dir.join(PICTURE), picture_svg(last, result)?.as_bytes())
}

/// Frames a run of `outputs` output times (t = 0 included) writes with
/// stride `every` (the last one always), and their bytes for `particles`
/// particles.
pub fn series_size(outputs: u64, every: u64, particles: usize) -> (u64, f64) {
    let every = every.max(1);
    let frames =
        outputs.div_ceil(every) + u64::from(outputs > 0 && !(outputs - 1).is_multiple_of(every));
    (
        frames,
        frames as f64 * particles as f64 * VTU_BYTES_PER_PARTICLE,
    )
}

/// Output times of a run to `t_end` at `interval` (t = 0 and t_end included).
pub fn output_times(t_end: f64, interval: f64) -> u64 {
    1 + (t_end / interval * (1.0 - 1e-9)).ceil().max(1.0) as u64
}
