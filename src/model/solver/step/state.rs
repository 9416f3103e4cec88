//! The particle state (structure of arrays), its start on the lattice, and
//! the per-step constants the pair loops read ([`Params`]).

use crate::problem::lattice::LatticeGeometry;
use crate::problem::{Initial, PressureForm, Problem};

/// Fluid particles come first (indices < n_fluid), the fixed walls after.
pub(crate) struct State {
    pub n_fluid: usize,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Velocity: v(t) between steps, v(t + dt/2) inside one. Zero on walls.
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    /// The velocity the forces see, v(t) + dt a(t), a prediction of
    /// v(t + dt) (viscosity and artificial viscosity depend on it).
    pub v_pred_x: Vec<f64>,
    pub v_pred_y: Vec<f64>,
    /// Acceleration of the fluid particles.
    pub ax: Vec<f64>,
    pub ay: Vec<f64>,
    pub rho: Vec<f64>,
    pub press: Vec<f64>,
    /// m / rho and P / rho^2, per particle, so the pair loops do not divide.
    pub vol: Vec<f64>,
    pub p_rho2: Vec<f64>,
    /// Fluid positions at the last neighbour-list rebuild.
    pub x0: Vec<f64>,
    pub y0: Vec<f64>,
    /// Each fluid particle's speed along x in the shear reference of the
    /// last rebuild ([`Self::shear_reference`]): the rebuild rule bounds
    /// displacements from x0 + u_ref t, not from x0. 0 where no rebuild
    /// took a reference (the list a run starts with, a run that keeps its
    /// start's order).
    pub u_ref: Vec<f64>,
    /// Layer each particle started in.
    pub layer: Vec<i32>,
    /// Each particle's index at the start (storage order changes at list
    /// rebuilds, [`State::reorder`]): walls keep theirs.
    pub id: Vec<u32>,
    /// How far beyond the no-slip plane |y| = B each particle sits: |y| - B
    /// for the walls (which never move), 0 for the fluid. For mirrored walls.
    pub depth: Vec<f64>,
    /// What the kernel pass leaves for the density sums: W of every listed
    /// pair (0 beyond the support), evaluated once per pair and step, in
    /// the pair table's place of the own entry it was evaluated for
    /// ([`NeighbourList::own_stream`], `pair_slots` of them), and after
    /// them a place kept at zero for padding; each entry finds its pair's
    /// through [`NeighbourList::sources_padded`].
    pub pair_w: Vec<f64>,
    pub pair_slots: usize,
    /// What it leaves for the force pass: (dW/dq)/q of every pair in both
    /// window lanes that list it, LANES per
    /// [`crate::solver::neighbours::Window`] in the list's order
    /// ([`NeighbourList::lanes_of_pairs`]), 0 in a lane not listed; for
    /// the list build `lane_generation` ([`NeighbourList::generation`]),
    /// whose lanes not listed it zeroed. The force pass has no distance
    /// test and no kernel.
    pub lane_g: Vec<f64>,
    pub lane_generation: u64,
    /// Or (the kernel pass's other form, [`super::GForm`]) (dW/dq)/q in
    /// the pair table's places as W is, with the zero place after them,
    /// for the force pass to gather.
    pub pair_g: Vec<f64>,
    /// The list build the last kernel pass ran on, and the form it left
    /// (dW/dq)/q in: the force pass reads it there.
    pub g_written: (u64, super::GForm),
}

/// Whether `order` (fluid particles as (band, x bits, index), sorted by
/// band, x and id) names, block by block of `block`, the particles stored
/// in that block in sorted order from one of them on: every block one
/// band, in x order up to a rotation. [`State::reorder`] decides this
/// without sorting; the tests hold it to this definition.
#[cfg(test)]
pub(crate) fn blocks_rotated(order: &[(u64, u64, u32)], block: usize) -> bool {
    order.chunks(block).enumerate().all(|(k, seg)| {
        let first = k * block;
        let r = (seg[0].2 as usize).wrapping_sub(first);
        r < block
            && seg
                .iter()
                .enumerate()
                .all(|(m, &(_, _, i))| i as usize == first + (r + m) % block)
    })
}

impl State {
    pub fn new(lattice: &LatticeGeometry, problem: &Problem) -> Self {
        let (mut x, mut y, layer) = lattice.positions();
        let n = x.len();
        let n_fluid = lattice.n_fluid();
        let jitter = problem.jitter * lattice.d;
        if jitter > 0.0 {
            // Seed 0 is the generator's original seed, so a scene without
            // `jitter_seed` keeps the lattice it always had.
            let mut rng = SplitMix64(0x5eed_5be5 ^ u64::from(problem.scene.jitter_seed));
            for i in 0..n_fluid {
                x[i] += jitter * rng.symmetric();
                y[i] += jitter * rng.symmetric();
            }
        }
        let mut vx = vec![0.0; n];
        if problem.initial == Initial::Steady {
            for i in 0..n_fluid {
                vx[i] = problem.flow.steady(y[i]);
            }
        }
        let b = lattice.b();
        let depth = (0..n)
            .map(|i| {
                if i < n_fluid {
                    0.0
                } else {
                    (y[i].abs() - b).max(0.0)
                }
            })
            .collect();
        State {
            n_fluid,
            depth,
            v_pred_x: vx.clone(),
            vx,
            vy: vec![0.0; n],
            v_pred_y: vec![0.0; n],
            ax: vec![0.0; n_fluid],
            ay: vec![0.0; n_fluid],
            rho: vec![problem.rho0; n],
            press: vec![0.0; n],
            vol: vec![0.0; n],
            p_rho2: vec![0.0; n],
            x0: x[..n_fluid].to_vec(),
            y0: y[..n_fluid].to_vec(),
            u_ref: vec![0.0; n_fluid],
            x,
            y,
            layer,
            id: (0..n as u32).collect(),
            pair_slots: usize::MAX,
            pair_w: Vec::new(),
            lane_g: Vec::new(),
            lane_generation: u64::MAX,
            pair_g: Vec::new(),
            g_written: (u64::MAX, super::GForm::Gather),
        }
    }

    /// Frees where the kernel pass leaves (dW/dq)/q in the form other than
    /// `form` (the steps take `form` until their pick's next trial).
    pub(crate) fn free_g_but(&mut self, form: super::GForm) {
        match form {
            super::GForm::Lanes => self.pair_g = Vec::new(),
            super::GForm::Gather => {
                self.lane_g = Vec::new();
                self.lane_generation = u64::MAX;
            }
        }
    }

    /// Bytes held by the arrays.
    pub fn bytes(&self) -> usize {
        let f64s = [
            &self.x,
            &self.y,
            &self.vx,
            &self.vy,
            &self.v_pred_x,
            &self.v_pred_y,
            &self.ax,
            &self.ay,
            &self.rho,
            &self.press,
            &self.vol,
            &self.p_rho2,
            &self.x0,
            &self.y0,
            &self.u_ref,
            &self.depth,
        ]
        .iter()
        .map(|v| v.capacity())
        .sum::<usize>();
        (f64s + self.pair_w.capacity() + self.lane_g.capacity() + self.pair_g.capacity())
            * size_of::<f64>()
            + (self.layer.capacity() + self.id.capacity()) * size_of::<u32>()
    }

    /// Store the fluid particles band by band in y, by x within a band
    /// (ties by id), so that a row of a particle's neighbours is a run of
    /// consecutive indices, as a layer of the lattice is at the start.
    /// Call after [`Self::wrap`]. Nothing moves while every block of
    /// `block` particles is already one band `band` high from `y_low` (a
    /// layer), in x order from some particle on (a layer sheared past the
    /// strip's edge is such a rotation): a lattice that keeps its order
    /// keeps its storage, and its results their bits. Otherwise the bands
    /// are `layers` such bands high: a row of a particle's neighbours in a
    /// band of several layers is a longer run, which fills more of the
    /// force pass's window ([`crate::solver::neighbours::Window`]).
    /// Deterministic, so results do not depend on the thread count.
    /// Returns whether the fluid is stored in bands (its lattice's order
    /// lost).
    pub fn reorder(
        &mut self,
        y_low: f64,
        band: f64,
        layers: usize,
        block: usize,
        order: &mut Vec<(u64, u64, u32)>,
    ) -> bool {
        let nf = self.n_fluid;
        let band_of = |y: f64, height: f64| ((y - y_low) / height).max(0.0) as u64;
        let sorted = |order: &mut Vec<(u64, u64, u32)>, height: f64| {
            order.clear();
            order.extend((0..nf).map(|i| {
                // x >= 0 after wrap: its bits order as its value.
                (band_of(self.y[i], height), self.x[i].to_bits(), i as u32)
            }));
            order.sort_unstable_by_key(|&(b, x, i)| (b, x, self.id[i as usize]));
        };
        // A block in sorted order from some particle on has its layers'
        // bands in order from there too: they descend at most once. A
        // fluid with a block whose bands descend more often (every
        // disordered fluid stored in bands of several layers) cannot keep
        // its order, and the sort that would decide it is skipped.
        let may_keep = self.y[..nf].chunks(block).all(|ys| {
            let bands = ys.iter().map(|&y| band_of(y, band));
            bands
                .clone()
                .zip(bands.skip(1))
                .filter(|(a, b)| b < a)
                .count()
                <= 1
        });
        if may_keep {
            // Whether sorting by (band, x, id) would find every block in
            // order from one of its particles on (what the tests call
            // `blocks_rotated`), decided without sorting: the keys are
            // distinct (ids are), so that holds exactly when each block,
            // read on from its least key (a last block short of `block`
            // from its first), ascends, and into the next block's least.
            let key = |i: usize| (band_of(self.y[i], band), self.x[i].to_bits(), self.id[i]);
            let mut last = None;
            let rotated = (0..nf.div_ceil(block)).all(|k| {
                let first = k * block;
                let len = block.min(nf - first);
                let at = |m: usize| first + m % len;
                let r = if len < block {
                    0
                } else {
                    (0..len).min_by_key(|&m| key(first + m)).unwrap_or(0)
                };
                let ascends = last.is_none_or(|l| l < key(at(r)))
                    && (r..r + len - 1).all(|m| key(at(m)) < key(at(m + 1)));
                last = Some(key(at(r + len - 1)));
                ascends
            });
            if rotated {
                return false;
            }
            if layers == 1 {
                sorted(order, band);
            }
        }
        if !may_keep || layers > 1 {
            sorted(order, layers as f64 * band);
        }
        fn permute<T: Copy>(v: &mut [T], order: &[(u64, u64, u32)], tmp: &mut Vec<T>) {
            tmp.clear();
            tmp.extend(order.iter().map(|&(_, _, i)| v[i as usize]));
            v[..order.len()].copy_from_slice(tmp);
        }
        let mut f = Vec::with_capacity(nf);
        for v in [
            &mut self.x,
            &mut self.y,
            &mut self.vx,
            &mut self.vy,
            &mut self.v_pred_x,
            &mut self.v_pred_y,
            &mut self.ax,
            &mut self.ay,
            &mut self.rho,
            &mut self.press,
            &mut self.vol,
            &mut self.p_rho2,
        ] {
            permute(v, order, &mut f);
        }
        let mut l = Vec::with_capacity(nf);
        permute(&mut self.layer, order, &mut l);
        let mut d = Vec::with_capacity(nf);
        permute(&mut self.id, order, &mut d);
        self.x0.copy_from_slice(&self.x[..nf]);
        self.y0.copy_from_slice(&self.y[..nf]);
        true
    }

    /// The shear reference of the rebuild rule
    /// ([`crate::solver::neighbours::NeighbourList::stale`]): a profile
    /// u(y) of the fluid's x velocity, piecewise linear through the mean
    /// v_x of each band `band` high from `y_low` (at its centre, where the
    /// centre is at least half a band inside the no-slip planes |y| = `b`:
    /// no two points nearer than that, whatever the rounding) and through
    /// 0 at those planes (the walls rest), 0 beyond them. Each fluid particle's
    /// u at its position is kept in `u_ref`; returns the profile's
    /// Lipschitz constant (its steepest piece), which the rule needs: two
    /// particles' references part by at most that times their distance in
    /// y per unit time. Call after [`Self::reorder`].
    pub fn shear_reference(&mut self, y_low: f64, band: f64, b: f64) -> f64 {
        let nf = self.n_fluid;
        // The bands up to the upper plane; a particle beyond it (or not
        // finite) counts in the last, whose centre is outside.
        let bands = ((b - y_low) / band).ceil().max(0.0) as usize + 1;
        let band_of = |y: f64| (((y - y_low) / band).max(0.0) as usize).min(bands - 1);
        let mut sums = vec![(0.0, 0u32); bands];
        for (&y, &v) in self.y[..nf].iter().zip(&self.vx[..nf]) {
            let s = &mut sums[band_of(y)];
            *s = (s.0 + v, s.1 + 1);
        }
        let mut nodes = vec![(-b, 0.0)];
        nodes.extend(sums.iter().enumerate().filter_map(|(k, &(sum, count))| {
            let centre = y_low + (k as f64 + 0.5) * band;
            (count > 0 && centre.abs() <= b - 0.5 * band).then(|| (centre, sum / f64::from(count)))
        }));
        nodes.push((b, 0.0));
        let slope = nodes
            .windows(2)
            .map(|w| ((w[1].1 - w[0].1) / (w[1].0 - w[0].0)).abs())
            .fold(0.0f64, f64::max);
        if !(slope.is_finite() && nodes.iter().all(|n| n.1.is_finite())) {
            // A state that is not finite (about to be reported): no
            // reference, the rule as for a lattice.
            self.u_ref.fill(0.0);
            return 0.0;
        }
        let profile = |y: f64| {
            let k = nodes.partition_point(|n| n.0 <= y);
            if k == 0 || k == nodes.len() {
                return 0.0;
            }
            let ((ya, ua), (yb, ub)) = (nodes[k - 1], nodes[k]);
            ua + (ub - ua) * ((y - ya) / (yb - ya))
        };
        for (u, &y) in self.u_ref.iter_mut().zip(&self.y0) {
            *u = profile(y);
        }
        slope
    }

    /// The positions the shear reference reaches in time `tau` (x0 +
    /// u_ref tau for the fluid, the walls where they are), wrapped into
    /// the strip, into `out`, for a list built ahead
    /// ([`crate::solver::neighbours::Reach`]). A fluid particle whose
    /// position ahead wraps across an edge of the strip is moved by the
    /// strip's width too (with its x0, so its displacement stays): its
    /// position and its position ahead then differ by u_ref tau alone,
    /// and the list's images hold for both. Call after
    /// [`Self::shear_reference`], which set x0 = x.
    pub fn ahead(&mut self, tau: f64, width: f64, out: &mut Vec<f64>) {
        let nf = self.n_fluid;
        out.clear();
        out.extend_from_slice(&self.x);
        let fluid = self.x[..nf].iter_mut().zip(&mut self.x0).zip(&self.u_ref);
        for (((x, x0), &u), out) in fluid.zip(&mut out[..nf]) {
            let ahead = *x + u * tau;
            let wrapped = ahead.rem_euclid(width);
            let turns = ((ahead - wrapped) / width).round();
            *out = wrapped;
            if turns != 0.0 {
                *x -= turns * width;
                *x0 = *x;
            }
        }
    }

    /// Wrap the fluid into the strip and take the current positions as the
    /// reference for the rebuild rule.
    pub fn wrap(&mut self, width: f64) {
        for i in 0..self.n_fluid {
            self.x[i] = self.x[i].rem_euclid(width);
        }
        self.x0.copy_from_slice(&self.x[..self.n_fluid]);
        self.y0.copy_from_slice(&self.y[..self.n_fluid]);
    }
}

/// A small deterministic generator (SplitMix64) for the initial jitter.
pub(super) struct SplitMix64(u64);

impl SplitMix64 {
    /// Uniform in [-1, 1).
    fn symmetric(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// Everything the pair loops need, with the h powers folded in once.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Params {
    pub inv_h2: f64,
    /// m / h^2: rho = (m / h^2) sum w(q^2).
    pub mass_over_h2: f64,
    pub mass: f64,
    pub rho0: f64,
    /// rho0 c0^2 / gamma.
    pub b_eos: f64,
    pub gamma: f64,
    pub allow_negative: bool,
    pub symmetric: bool,
    /// grad_i W_ij = (dw_over_q / h^4) r_ij.
    pub grad_scale: f64,
    /// alpha c0 h m (31).
    pub av: f64,
    /// Whether (31) acts at all: [`Problem::has_artificial_viscosity`], the
    /// same test the flop count makes.
    pub has_av: bool,
    /// 2 mu (the Laplacian (14) with the right sign), times
    /// [`Problem::viscous_scale`] (1 unless normalised by the lattice).
    pub visc: f64,
    /// Body force along +x.
    pub body: f64,
    /// Walls mirror the fluid's velocity in the viscous term ([`super::forces::forces`]).
    pub mirror_walls: bool,
    /// The no-slip plane |y| = B.
    pub b: f64,
    /// The cap on the mirrored walls' factor beta = 1 + D_j / g_i: the
    /// largest beta of the undisturbed lattice (the deepest wall layer, at
    /// D = (layers - 1) dy, seen from the first fluid layer, g = dy), so
    /// that only a fluid particle nearer the plane than one layer spacing
    /// is capped, and a particle reaching the plane does not take an
    /// unbounded viscous force. Morris, Fox and Zhu (1997) capped it at
    /// 1.5; one, two and three wall layers give 1, 2 and 3 here.
    pub beta_max: f64,
}

impl Params {
    pub fn new(problem: &Problem) -> Self {
        let h = problem.lattice.h;
        Params {
            inv_h2: 1.0 / (h * h),
            mass_over_h2: problem.mass / (h * h),
            mass: problem.mass,
            rho0: problem.rho0,
            b_eos: problem.rho0 * problem.c0 * problem.c0 / problem.gamma,
            gamma: problem.gamma,
            allow_negative: problem.allow_negative_pressure,
            symmetric: problem.pressure_form == PressureForm::Symmetric,
            grad_scale: 1.0 / (h * h * h * h),
            av: problem.alpha * problem.c0 * h * problem.mass,
            has_av: problem.has_artificial_viscosity(),
            visc: 2.0 * problem.mu * problem.viscous_scale,
            body: problem.flow.p,
            mirror_walls: problem.mirrored_walls(),
            b: problem.lattice.b(),
            beta_max: f64::from(problem.lattice.wall_layers.max(1)),
        }
    }

    /// EOS (13): P = rho0 c0^2 / gamma ((rho/rho0)^gamma - 1), no tension
    /// unless allowed, from the compression (rho/rho0)^gamma - 1: the
    /// density pass forms it, choosing its form (gamma = 1 or the power)
    /// once per loop.
    #[inline(always)]
    pub(super) fn pressure_of(&self, compression: f64) -> f64 {
        let p = self.b_eos * compression;
        if self.allow_negative {
            p
        } else {
            p.max(0.0)
        }
    }
}
