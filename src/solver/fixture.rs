//! TEMPORARY hand-written kernel and registry, until the generated kernels
//! (`crate::kernels`) land. Only Monaghan's cubic spline (23), R = 2, and a
//! registry of that one kernel with the same shape as the generated one.
//! Delete this file when `generated/registry.rs` exists.

use std::f64::consts::PI;

use crate::kernel::{C0Model, Derived, EpsInfo, Kernel, KernelInfo, KernelVisitor, PrintedC0};

/// Monaghan cubic spline, R = 2 (the paper's (23)).
#[derive(Debug, Clone, Copy, Default)]
pub struct Monaghan;

const SIGMA: f64 = 15.0 / (7.0 * PI);

impl Kernel for Monaghan {
    const NAME: &'static str = "monaghan";
    const SUPPORT: f64 = 2.0;
    const SUPPORT2_CLOSED: f64 = 4.0 * (1.0 + 1e-9);
    const INFO: &'static KernelInfo = &MONAGHAN_INFO;

    fn w(q2: f64) -> f64 {
        let q = q2.sqrt();
        if q <= 1.0 {
            SIGMA * (2.0 / 3.0 - q2 + 0.5 * q2 * q)
        } else if q <= 2.0 {
            let s = 2.0 - q;
            SIGMA * s * s * s / 6.0
        } else {
            0.0
        }
    }

    fn dw(q2: f64) -> f64 {
        let q = q2.sqrt();
        if q <= 1.0 {
            SIGMA * (-2.0 * q + 1.5 * q2)
        } else if q <= 2.0 {
            let s = 2.0 - q;
            -SIGMA * 0.5 * s * s
        } else {
            0.0
        }
    }

    fn dw_over_q(q2: f64) -> f64 {
        let q = q2.sqrt();
        if q <= 1.0 {
            SIGMA * (-2.0 + 1.5 * q)
        } else if q <= 2.0 {
            let s = 2.0 - q;
            -SIGMA * 0.5 * s * s / q
        } else {
            0.0
        }
    }
}

const fn printed(value: f64) -> Derived {
    Derived {
        value,
        exact: "",
        is_exact: false,
    }
}

fn eps_unknown(_t: f64, _n: u32) -> f64 {
    f64::NAN
}

/// Table 2's printed row recast as a model, so `derived` resolves to
/// something until the generator's models exist:
/// 10 (sqrt(6 a^2 + 5 A) - 2.15 a) = sqrt(600 a^2 + 500 A) - 21.5 a.
static MONAGHAN_MODELS: [C0Model; 1] = [C0Model {
    name: "printed",
    description: "Table 2 as printed (fixture only)",
    a: printed(f64::NAN),
    b: printed(f64::NAN),
    c: printed(f64::NAN),
    s: printed(21.5),
    p: printed(600.0),
    q: printed(500.0),
}];

static MONAGHAN_INFO: KernelInfo = KernelInfo {
    name: "monaghan",
    title: "Monaghan cubic spline (R = 2), hand-written fixture",
    reference: "Monaghan 2005; Reshetnikova 2024, eq. (23)",
    support: 2.0,
    support_exact: "2",
    eps: EpsInfo {
        t0: printed(-0.004120),
        half_period: printed(0.001984),
        max: printed(f64::NAN),
        t_max: printed(f64::NAN),
        min: printed(f64::NAN),
        t_min: printed(f64::NAN),
        mean: printed(-0.001275),
    },
    c0_default: "printed",
    c0_models: &MONAGHAN_MODELS,
    printed_c0: Some(PrintedC0 {
        eps0: 0.00198,
        factor: 10.0,
        s: 2.15,
        p: 6.0,
        q: 5.0,
    }),
    stencil_t0: &[],
    stencil_half: &[],
    eps_at: eps_unknown,
    flops_per_pair: 0,
};

pub static KERNELS: &[&KernelInfo] = &[&MONAGHAN_INFO];

pub fn kernel_info(name: &str) -> Option<&'static KernelInfo> {
    KERNELS.iter().copied().find(|k| k.name == name)
}

pub fn with_kernel<V: KernelVisitor>(name: &str, v: V) -> Option<V::Output> {
    match name {
        "monaghan" => Some(v.visit::<Monaghan>()),
        _ => None,
    }
}
