//! What a scene names, found: the kernel by name, its discretisation by
//! lattice and h/d.

use super::HOverD;

use super::{invalid, SceneError};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo, Lattice};
use crate::kernels;

/// The generated discretisation of `info` a scene names (its `lattice` and
/// `h_over_d`), or an error naming the line to add to
/// kernels/discretisations.toml and the command to run.
pub fn discretisation(
    info: &'static KernelInfo,
    lattice: Lattice,
    h_over_d: f64,
) -> Result<&'static DiscretisationInfo, SceneError> {
    // the generator derives 0 < h/d <= 4 (codegen's MAX_H_OVER_D): outside
    // it there is no line to add, only a value to change
    if !(h_over_d > 0.0 && h_over_d <= 4.0) {
        return Err(invalid(
            "h_over_d",
            format!(
                "{} is outside (0, 4], the h/d the generator derives; use a generated one (1, 13/10, ...)",
                fmt_value(h_over_d)
            ),
        ));
    }
    info.discretisation(lattice, h_over_d).ok_or_else(|| {
        let known: Vec<String> = info.discretisations.iter().map(|d| d.label()).collect();
        invalid(
            "h_over_d",
            format!(
                "kernel {} has no generated discretisation with lattice = {:?} and h = {} d \
                 (generated: {}); add to kernels/discretisations.toml\n\n[[discretisation]]\n\
                 lattice = \"{}\"\nh_over_d = {}\n\nthen run `cargo run -p shearsph-codegen -- generate` \
                 and rebuild",
                info.name,
                lattice.name(),
                fmt_value(h_over_d),
                known.join("; "),
                lattice.name(),
                HOverD::toml_text(h_over_d),
            ),
        )
    })
}

/// A kernel's data by name, or an error listing the known kernels and
/// suggesting the nearest name.
pub fn kernel_info(name: &str) -> Result<&'static KernelInfo, SceneError> {
    kernels::kernel_info(name).ok_or_else(|| {
        let nearest = kernels::NAMES
            .iter()
            .map(|k| (strsim::levenshtein(name, k), *k))
            .min()
            .filter(|(dist, k)| *dist <= k.len().max(2) / 2)
            .map(|(_, k)| format!("; did you mean {k:?}?"))
            .unwrap_or_default();
        SceneError::UnknownKernel {
            name: name.to_string(),
            known: format!("{}{nearest}", kernels::NAMES.join(", ")),
        }
    })
}
