//! The channel of a scene: the lattice and the flow (B, p, nu, Re). It needs
//! no sound speed, so c0 by any rule, and its cost, can be computed from it
//! without resolving a whole problem.

use crate::analytic::Poiseuille;
use crate::config::{invalid, positive, Scene, SceneError};
use crate::kernel::{DiscretisationInfo, KernelInfo};

use super::lattice::{Lattice, CLOSED_TOL};

/// The lattice and the flow of a scene, for one kernel.
#[derive(Debug, Clone)]
pub struct Channel {
    pub lattice: Lattice,
    /// What the generator derived for the scene's lattice and h/d: the c0
    /// models and eps the scene's c0 and checks use.
    pub discretisation: &'static DiscretisationInfo,
    /// Walls at y = ±B, U, nu and p.
    pub flow: Poiseuille,
    pub re: f64,
}

impl Channel {
    /// Check the fields the channel reads and build it. The skin is checked
    /// here because its range is the kernel's support.
    pub fn resolve(scene: &Scene, info: &'static KernelInfo) -> Result<Channel, SceneError> {
        let discretisation = scene.discretisation(info)?;
        let d = scene.d;
        let h = scene.h_over_d * d;
        let support = info.support;
        if !(scene.skin > 0.0 && scene.skin < support) {
            return Err(invalid(
                "skin",
                format!(
                    "{} (in h) must be in (0, R) = (0, {support}) for kernel {}",
                    scene.skin, info.name
                ),
            ));
        }
        let lattice = Lattice::new(scene.lattice, scene.n_layers, d, h, support);
        // The centre line's support must not reach the wall (closed support).
        let n_min = (support * h * (1.0 + CLOSED_TOL) / lattice.dy).floor() as u32 + 1;
        if scene.n_layers < n_min {
            return Err(invalid(
                "n_layers",
                format!(
                    "{} is too small for kernel {} (support R = {support}, h = {} d): the centre layer's \
                     support reaches the wall; use n_layers >= {n_min}",
                    scene.n_layers, info.name, scene.h_over_d
                ),
            ));
        }
        let b = lattice.b();
        let flow = match (scene.re, scene.p) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "re",
                    "both `re` and `p` are given; they fix the same thing: keep one",
                ));
            }
            (None, None) => return Err(invalid("re", "give `re` (or `p`, the body force)")),
            (Some(re), None) => {
                positive("re", re)?;
                Poiseuille::from_re(scene.u, b, re)
            }
            (None, Some(p)) => {
                positive("p", p)?;
                Poiseuille::from_p(scene.u, b, p)
            }
        };
        Ok(Channel {
            lattice,
            discretisation,
            re: flow.re(),
            flow,
        })
    }

    /// The scene's end time, or by default the time for the start-up's
    /// slowest mode to fall below `decay_tol` U.
    pub fn t_end(&self, scene: &Scene) -> Result<f64, SceneError> {
        match scene.t_end {
            Some(t) => {
                positive("t_end", t)?;
                Ok(t)
            }
            None => Ok(self.flow.decay_time(scene.decay_tol)),
        }
    }

    /// The paper's parameter of Table 2, A = p d N^4 / U^2.
    pub fn a_param(&self) -> f64 {
        let n = f64::from(self.lattice.n_layers);
        self.flow.p * self.lattice.d * n.powi(4) / (self.flow.u * self.flow.u)
    }
}
