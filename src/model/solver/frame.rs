//! The particle field at one output time, as the solver holds it, lent to
//! an observer ([`super::Observer::particles`]); `crate::particles` writes
//! it for ParaView and draws it. Only built when an observer asks, and only
//! at output times: the steps between pay nothing.

use super::step::State;
use crate::problem::Problem;

/// The particle field at one time (structure of arrays, all of one length).
#[derive(Debug, Clone, Copy)]
pub struct ParticleFrame<'a> {
    pub time: f64,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub vx: &'a [f64],
    pub vy: &'a [f64],
    pub density: &'a [f64],
    pub pressure: &'a [f64],
    /// Compaction eps = rho / rho0 - 1.
    pub eps: &'a [f64],
    /// Wall particle (true) or fluid (false).
    pub wall: &'a [bool],
    /// Layer index n (the paper's layer; walls continue the count).
    pub layer: &'a [i32],
}

/// What a frame needs beyond the state's own arrays, kept between outputs
/// so an output allocates nothing after the first: x wrapped into the strip
/// (it runs past the edges between list rebuilds), eps, the wall flags;
/// and, once the solver has reordered the fluid ([`State::reorder`]), every
/// field in the start's order, so that particle k of every frame is the
/// same particle.
#[derive(Debug, Default)]
pub(super) struct FrameBuf {
    x: Vec<f64>,
    eps: Vec<f64>,
    wall: Vec<bool>,
    /// For each particle (the start's index), where the state holds it.
    at: Vec<usize>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    rho: Vec<f64>,
    press: Vec<f64>,
    layer: Vec<i32>,
}

impl FrameBuf {
    /// The frame of `s` at time `t`.
    pub fn frame<'a>(&'a mut self, s: &'a State, problem: &Problem, t: f64) -> ParticleFrame<'a> {
        let n = s.x.len();
        let width = problem.lattice.width;
        self.at.resize(n, 0);
        for (k, &id) in s.id.iter().enumerate() {
            self.at[id as usize] = k;
        }
        let at = &self.at;
        self.x.clear();
        self.x.extend(at.iter().map(|&k| s.x[k].rem_euclid(width)));
        self.eps.clear();
        self.eps
            .extend(at.iter().map(|&k| s.rho[k] / problem.rho0 - 1.0));
        if self.wall.len() != n {
            self.wall = (0..n).map(|i| i >= s.n_fluid).collect();
        }
        if at.iter().enumerate().all(|(i, &k)| i == k) {
            return ParticleFrame {
                time: t,
                x: &self.x,
                y: &s.y,
                vx: &s.vx,
                vy: &s.vy,
                density: &s.rho,
                pressure: &s.press,
                eps: &self.eps,
                wall: &self.wall,
                layer: &s.layer,
            };
        }
        let gather = |out: &mut Vec<f64>, v: &[f64]| {
            out.clear();
            out.extend(at.iter().map(|&k| v[k]));
        };
        gather(&mut self.y, &s.y);
        gather(&mut self.vx, &s.vx);
        gather(&mut self.vy, &s.vy);
        gather(&mut self.rho, &s.rho);
        gather(&mut self.press, &s.press);
        self.layer.clear();
        self.layer.extend(at.iter().map(|&k| s.layer[k]));
        ParticleFrame {
            time: t,
            x: &self.x,
            y: &self.y,
            vx: &self.vx,
            vy: &self.vy,
            density: &self.rho,
            pressure: &self.press,
            eps: &self.eps,
            wall: &self.wall,
            layer: &self.layer,
        }
    }
}
