//! The channel of a scene: the lattice and the flow (B, p, nu, Re). It needs
//! no sound speed, so c0 by any rule, and its cost, can be computed from it
//! without resolving a whole problem.

use crate::analytic::Poiseuille;
use crate::config::{invalid, positive, Scene, SceneError};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo};

use super::cost::DtFactors;
use super::lattice::{LatticeGeometry, CLOSED_TOL};

/// The lattice and the flow of a scene, for one kernel.
#[derive(Debug, Clone)]
pub struct Channel {
    pub lattice: LatticeGeometry,
    /// What the generator derived for the scene's lattice and h/d: the c0
    /// models and eps the scene's c0 and checks use.
    pub discretisation: &'static DiscretisationInfo,
    /// Walls at y = ±B, U, nu and p.
    pub flow: Poiseuille,
    pub re: f64,
    /// The scene's time-step factors (`cfl`, `viscous_dt`): what the
    /// estimates of the step, the steps and the run time take.
    pub dt_factors: DtFactors,
}

/// The strip of a jittered start, unless the scene sets `columns`: at
/// least as wide as the channel, 2B (the disordered state it grows into is
/// what its window judges), since a
/// narrower periodic strip falls back into order at high c0 where a wide
/// one stays disordered (docs/stationary.md: Monaghan, N = 10, Re = 1,
/// 30 U: eps_stat 0.003 on 5 columns, 0.010 on 10, 0.011 on 20; at 20 U 20
/// and 40 columns agree).
/// The most columns a strip may have: a bound that says why, as the
/// particle count grows with it and the memory check (check_size) sees only
/// the narrowest.
pub const MAX_COLUMNS: u32 = 100_000;

fn disordered_columns(scene: &Scene, lattice: &LatticeGeometry) -> Option<u32> {
    let wide = scene.jitter > 0.0;
    let channel = (2.0 * lattice.b() / lattice.d * (1.0 - 1e-12)).ceil();
    (wide && channel > f64::from(lattice.columns) && channel <= 1e5).then_some(channel as u32)
}

/// Err unless the support R h reaches a particle's nearest neighbours on
/// the lattice (at d on either lattice: in the row, and diagonally on the
/// triangular one) and so at least one wall layer: below, no particle sees
/// another, the density is its own, there are no walls and no shear. Named
/// as `h_over_d`, the field that makes the reach.
pub fn check_interacts(lattice: &LatticeGeometry, info: &KernelInfo) -> Result<(), SceneError> {
    let reach = info.support * lattice.h * (1.0 + CLOSED_TOL);
    if reach >= lattice.d && lattice.wall_layers >= 1 {
        return Ok(());
    }
    Err(invalid(
        "h_over_d",
        format!(
            "h = {} d gives kernel {} (support R = {}) a reach of {} d, short of the nearest \
             neighbours at d: no particle would see another and the channel has {} wall layers; \
             give h_over_d >= {} (a discretisation of kernels/discretisations.toml with R h >= d)",
            fmt_value(lattice.h / lattice.d),
            info.name,
            fmt_value(info.support),
            fmt_value(info.support * lattice.h / lattice.d),
            lattice.wall_layers,
            fmt_value(1.0 / info.support)
        ),
    ))
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
                    fmt_value(scene.skin),
                    info.name
                ),
            ));
        }
        positive("d", d)?;
        positive("h_over_d", scene.h_over_d)?;
        super::cost::check_size(scene.lattice, scene.n_layers, d, h, support, scene.skin)?;
        let mut lattice = LatticeGeometry::new(scene.lattice, scene.n_layers, d, h, support);
        if let Some(c) = scene
            .columns
            .or_else(|| disordered_columns(scene, &lattice))
        {
            if !(lattice.columns..=MAX_COLUMNS).contains(&c) {
                return Err(invalid(
                    "columns",
                    format!(
                        "{c} must be from {} (the fewest whole columns wider than the support's \
                         diameter 2 R h for kernel {}) to {MAX_COLUMNS}",
                        lattice.columns, info.name
                    ),
                ));
            }
            lattice.columns = c;
            lattice.width = f64::from(c) * d;
            if lattice.n_particles() as f64 > super::cost::MAX_PARTICLES {
                return Err(invalid(
                    "columns",
                    format!(
                        "{c} columns give {} particles, above {}: use fewer",
                        lattice.n_particles(),
                        fmt_value(super::cost::MAX_PARTICLES)
                    ),
                ));
            }
        }
        // The method needs neighbours and walls: a support that reaches no
        // other site (h = 0.1 d with R = 2: 0.2 d, the nearest at d) leaves
        // every particle alone and the channel without wall layers.
        check_interacts(&lattice, info)?;
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
            dt_factors: DtFactors {
                cfl: scene.cfl.unwrap_or_else(|| {
                    super::cost::default_cfl(super::acoustic_stable_factor(
                        info,
                        &lattice,
                        super::Eos::of_scene(scene),
                    ))
                }),
                viscous: scene.viscous_dt.unwrap_or_else(|| {
                    super::cost::default_viscous_dt(super::viscous_stable_factor(
                        info,
                        &lattice,
                        scene.viscous_normalisation,
                    ))
                }),
            },
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
            None => {
                let tol = scene.decay_tol;
                let amplitude = 32.0 / std::f64::consts::PI.powi(3);
                if !(tol > 0.0 && tol < amplitude) {
                    return Err(invalid(
                        "decay_tol",
                        format!(
                            "{} must be in (0, {}), below the slowest start-up mode's amplitude \
                             32 / pi^3 U: at or above it the default end time is 0 (or set t_end)",
                            fmt_value(tol),
                            fmt_value(amplitude)
                        ),
                    ));
                }
                Ok(self.flow.decay_time(tol))
            }
        }
    }

    /// The inputs the flow (B, nu, p, Re) is computed from, for the error
    /// of a derived quantity that is not a finite positive number.
    pub fn flow_inputs(&self, scene: &Scene) -> Vec<(&'static str, f64)> {
        let mut v = vec![("d", scene.d), ("u", scene.u)];
        match (scene.re, scene.p) {
            (Some(re), _) => v.push(("re", re)),
            (None, Some(p)) => v.push(("p", p)),
            (None, None) => {}
        }
        v
    }

    /// B, nu, p, Re and A each finite and positive, or an error naming the
    /// input that made one not.
    pub fn check_derived(&self, scene: &Scene) -> Result<(), SceneError> {
        let n = f64::from(scene.n_layers);
        let inputs = self.flow_inputs(scene);
        let b_in = [("d", scene.d), ("n_layers", n)];
        super::derived("the half-width B = N dy", self.flow.b, &b_in)?;
        let all = super::with(&inputs, &[("n_layers", n)]);
        super::derived("the viscosity nu", self.flow.nu, &all)?;
        super::derived("the body force p", self.flow.p, &all)?;
        super::derived("the Reynolds number Re", self.re, &all)?;
        super::derived("the paper's A = p d N^4 / U^2", self.a_param(), &all)
    }

    /// The paper's parameter of Table 2, A = p d N^4 / U^2.
    pub fn a_param(&self) -> f64 {
        let n = f64::from(self.lattice.n_layers);
        self.flow.p * self.lattice.d * n.powi(4) / (self.flow.u * self.flow.u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::Lattice;

    #[test]
    fn a_support_that_reaches_no_neighbour_is_refused() {
        // h = 1/10 d (a discretisation a user could generate): R h = 0.2 d
        // for the cubic spline, short of the nearest site at d.
        let info = crate::config::kernel_info("monaghan").unwrap();
        for &kind in Lattice::ALL {
            let thin = LatticeGeometry::new(kind, 10, 1.0, 0.1, info.support);
            let e = check_interacts(&thin, info).unwrap_err().to_string();
            assert!(
                e.contains("`h_over_d`") && e.contains("no particle would see another"),
                "{e}"
            );
            assert!(
                e.contains("0 wall layers") && e.contains("h_over_d >= 0.5"),
                "{e}"
            );
            // The paper's h = d, and R h = d exactly (closed support), pass.
            let paper = LatticeGeometry::new(kind, 10, 1.0, 1.0, info.support);
            assert!(check_interacts(&paper, info).is_ok());
            let edge = LatticeGeometry::new(kind, 10, 1.0, 0.5, info.support);
            assert!(check_interacts(&edge, info).is_ok(), "{kind:?}");
        }
    }
}
