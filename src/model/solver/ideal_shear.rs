//! The compaction eps(t, n) measured by the solver's own density summation
//! (11) on particles held to the ideal shear: every fluid particle moved
//! exactly by the steady profile (7), x(t) = x(0) + u(y) t, y fixed, walls
//! at rest; no dynamics. This is the paper's section 4 set-up, so it must
//! reproduce the generated `KernelInfo::eps_at(t, n, Some(N))`; Figure 4 of
//! the report overlays the two.

use super::neighbours::NeighbourList;
use super::step::{self, Params, State};
use crate::kernel::{DiscretisationInfo, Kernel};
use crate::problem::lattice::LatticeGeometry;
use crate::problem::{Problem, SceneError};

/// eps = rho / rho0 - 1 of a particle of each layer in `layers` (0 <= n <
/// N), at each time in `t_over_period` (fractions of T = d N^2 / U), for N =
/// `n_layers` on discretisation `disc` (its lattice and h/d; the paper's is
/// `K::INFO.discretisations[0]`). `result[l][k]` is layer `layers[l]` at
/// time k.
pub fn eps_series<K: Kernel>(
    disc: &DiscretisationInfo,
    n_layers: u32,
    layers: &[u32],
    t_over_period: &[f64],
) -> Result<Vec<Vec<f64>>, SceneError> {
    let problem = Problem::ideal_shear(K::INFO, disc, n_layers)?;
    let lat: LatticeGeometry = problem.lattice;
    let mut s = State::new(&lat, &problem);
    let params = Params::new(&problem);
    let cutoff = K::SUPPORT2_CLOSED.sqrt() * lat.h + 0.5 * problem.skin * lat.h;
    let block = lat.columns as usize;
    let period = lat.d * f64::from(n_layers).powi(2) / problem.flow.u;
    let x0: Vec<f64> = s.x.clone();
    // A particle of each layer asked for.
    let pick: Vec<Result<usize, SceneError>> = layers
        .iter()
        .map(|&n| {
            (0..s.n_fluid)
                .find(|&i| s.layer[i] == n as i32)
                .ok_or_else(|| SceneError::Invalid {
                    field: "n_layers",
                    flag: "n",
                    message: format!(
                        "layer {n} is not a fluid layer of N = {n_layers} (0 <= n < N)"
                    ),
                })
        })
        .collect();
    let pick: Vec<usize> = pick.into_iter().collect::<Result<_, _>>()?;
    let mut out = vec![Vec::with_capacity(t_over_period.len()); layers.len()];
    let mut list = NeighbourList::default();
    for &tf in t_over_period {
        let t = tf * period;
        let nf = s.n_fluid;
        for ((x, &x0), &y) in s.x[..nf].iter_mut().zip(&x0).zip(&s.y[..nf]) {
            *x = x0 + problem.flow.steady(y) * t;
        }
        s.wrap(lat.width);
        list.build(&s.x, &s.y, lat.width, cutoff, block);
        step::density::<K>(&mut s, &list, &params);
        for (l, &i) in pick.iter().enumerate() {
            out[l].push(s.rho[i] / problem.rho0 - 1.0);
        }
    }
    Ok(out)
}
