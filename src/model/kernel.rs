//! The `Kernel` trait the solver is generic over, and the plain data the
//! generator emits for every kernel (see `generated/`, made by
//! `cargo run -p shearsph-codegen -- generate`; never edited by hand).
//!
//! Lengths inside kernel functions are in units of the smoothing length h:
//! `q = r / h`. Values are in units of h^-2 (W), h^-3 (dW/dq) and h^-4
//! ((dW/dq)/q). Functions take `q2 = q^2` so a kernel that is even in q needs
//! no square root; kernels with odd powers take it inside.

/// A smoothing kernel, specialised by the generator. Unit structs implement
/// it; the solver is generic over it so every call is static and inlined.
pub trait Kernel: Copy + Send + Sync + Default + 'static {
    /// Name as in `kernels/NAME.toml`.
    const NAME: &'static str;
    /// Squared support with a relative tolerance of 1e-9: lattice neighbours at
    /// exactly q = R count as inside (closed support, as in the derivation),
    /// whatever the f64 round-off of their distance.
    const SUPPORT2_CLOSED: f64;
    /// Everything the derivation found about this kernel.
    const INFO: &'static KernelInfo;
    /// W(q), units h^-2.
    fn w(q2: f64) -> f64;
    /// (W, (dW/dq)/q) of one pair (dW/dq the kernel's gradient function,
    /// which may be given separately from W; units h^-2 and h^-4), without
    /// branches, for pair loops that run in vector lanes: every piece in one
    /// form (one square root and one division per pair whatever the piece,
    /// none for a kernel even in q), its constants selected by q^2. A kernel
    /// of one piece (nothing to select), or whose W and W' pieces do not
    /// share their joints, keeps its branch and each piece's own forms. As
    /// accurate as W and (dW/dq)/q alone; (0, 0) beyond the support; finite
    /// at q = 0.
    fn w_dw_over_q_lanes(q2: f64) -> (f64, f64);
}

/// A number the generator derived: its f64 value (correctly rounded) and its
/// exact (or stated high-precision) form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Derived {
    pub value: f64,
    /// Exact form, e.g. `-1/2 + 3/(7*pi)*sqrt(3)`, or a decimal with its
    /// stated digits when the quantity is only known to high precision.
    pub exact: &'static str,
    /// `true` when `exact` is an exact closed form, `false` when it is a
    /// high-precision decimal (quadrature or search).
    pub is_exact: bool,
}

/// The compaction analysis of section 4 (eps = rho/rho0 - 1), for a particle
/// in layer n = 0 unless stated.
#[derive(Debug, Clone, Copy)]
pub struct EpsInfo {
    /// eps at t = 0 (undisturbed lattice).
    pub t0: Derived,
    /// eps at t = 0.5 T (odd layers shifted by d/2).
    pub half_period: Derived,
    /// True maximum over the period, and where (fraction of T).
    pub max: Derived,
    pub t_max: Derived,
    /// True minimum over the period, and where (fraction of T).
    pub min: Derived,
    pub t_min: Derived,
    /// Time mean over the period.
    pub mean: Derived,
}

/// One model of the c0 derivation: the polynomial
/// `a c0^2 + b alpha (U/N^2) c0 + c p d = 0` and its root
/// `c0 = (U/N^2) (sqrt(P alpha^2 + Q A) - S alpha)`, `A = p d N^4 / U^2`.
#[derive(Debug, Clone, Copy)]
pub struct C0Model {
    pub name: &'static str,
    pub description: &'static str,
    /// t / T of the configuration its coefficients come from: the maximum
    /// compaction's (`C0Configuration::t`), or for an `-av` model at a
    /// maximum off the symmetric configurations its mirror T - t when the
    /// model's c0 is larger there (the generator takes the stricter of the
    /// two instants; see `C0Configuration::label`).
    pub t: Derived,
    pub a: Derived,
    pub b: Derived,
    pub c: Derived,
    pub s: Derived,
    pub p: Derived,
    pub q: Derived,
}

impl C0Model {
    /// The model sound speed for a scene: u_max = U, n_layers = N, p the body
    /// force, d the particle spacing, alpha the artificial viscosity. NaN or
    /// not positive when the derivation has no positive root for the scene
    /// (e.g. Q < 0 with S > 0).
    pub fn c0(&self, u_max: f64, n_layers: f64, p: f64, d: f64, alpha: f64) -> f64 {
        let scale = u_max / (n_layers * n_layers);
        let (pc, qc, sc) = (self.p.value, self.q.value, self.s.value);
        scale * c0_root(pc, qc, sc, u_max, n_layers, p, d, alpha)
    }
}

/// The paper's printed row of Table 2 for a kernel, if it has one:
/// c0 = F U (sqrt(P alpha^2 + Q A) - S alpha) / N^2.
#[derive(Debug, Clone, Copy)]
pub struct PrintedC0 {
    pub eps0: f64,
    pub factor: f64,
    pub s: f64,
    pub p: f64,
    pub q: f64,
}

impl PrintedC0 {
    pub fn c0(&self, u_max: f64, n_layers: f64, p: f64, d: f64, alpha: f64) -> f64 {
        let root = c0_root(self.p, self.q, self.s, u_max, n_layers, p, d, alpha);
        self.factor * u_max * root / (n_layers * n_layers)
    }
}

/// The one root formula of the c0 polynomial, up to its scale U / N^2:
/// sqrt(P alpha^2 + Q A) - S alpha with A = p d N^4 / U^2. Both the derived
/// models and the paper's printed Table 2 rows evaluate it.
#[allow(clippy::too_many_arguments)]
pub fn c0_root(
    p_coef: f64,
    q_coef: f64,
    s_coef: f64,
    u_max: f64,
    n_layers: f64,
    p: f64,
    d: f64,
    alpha: f64,
) -> f64 {
    let a_big = p * d * n_layers.powi(4) / (u_max * u_max);
    (p_coef * alpha * alpha + q_coef * a_big).sqrt() - s_coef * alpha
}

/// The paper's Table 1 row for a kernel: eps at 0, at 0.5 T, and its mean.
#[derive(Debug, Clone, Copy)]
pub struct PrintedEps {
    pub t0: &'static str,
    pub half_period: &'static str,
    pub mean: &'static str,
}

/// All the generator knows about a kernel, as data for programs.
#[derive(Debug, Clone, Copy)]
pub struct KernelInfo {
    pub name: &'static str,
    pub title: &'static str,
    pub reference: &'static str,
    /// Support R in units of h.
    pub support: f64,
    pub support_exact: &'static str,
    pub eps: EpsInfo,
    /// Name of the default c0 model (one of `c0_models`).
    pub c0_default: &'static str,
    pub c0_models: &'static [C0Model],
    /// The paper's Table 2 row, when the kernel is one of the paper's.
    pub printed_c0: Option<PrintedC0>,
    /// eps(t, n) for a particle of layer n, t as a fraction of T; an
    /// unrolled sum over the layers in reach. `walls = Some(N)` puts fixed
    /// wall layers at |j| >= N (u = 0); `None` is an interior particle.
    pub eps_at: fn(t: f64, n: u32, walls: Option<u32>) -> f64,
    /// The paper's printed Table 1 row, as printed (strings keep the printed
    /// precision), when the kernel is one of the paper's.
    pub printed_eps: Option<PrintedEps>,
    /// Every discretisation the generator derived this kernel for (lattice
    /// kind, h/d; `kernels/discretisations.toml`), the paper's (triangular,
    /// h = d) first. The fields above are the paper's entry.
    pub discretisations: &'static [DiscretisationInfo],
    /// Floating-point operations per pair evaluation of (w, dw_over_q)
    /// together as the solver's pair loops run it (`Kernel::w_dw_over_q_lanes`:
    /// square root and division counted as one each, the piece tests
    /// included), as counted by the generator in the emitted code.
    pub flops_per_pair: u32,
}

impl KernelInfo {
    /// The derivation for a lattice and h/d, if it was generated (h/d
    /// matched to a relative 1e-12: `1.3` finds `13/10`). When it is
    /// missing, add a line to `kernels/discretisations.toml` and run
    /// `cargo run -p shearsph-codegen -- generate`.
    pub fn discretisation(
        &self,
        lattice: Lattice,
        h_over_d: f64,
    ) -> Option<&'static DiscretisationInfo> {
        self.discretisations.iter().find(|d| {
            d.lattice == lattice && (d.h_over_d - h_over_d).abs() <= 1e-12 * h_over_d.abs()
        })
    }
    pub fn c0_model(&self, name: &str) -> Option<&'static C0Model> {
        self.c0_models.iter().find(|m| m.name == name)
    }
    pub fn default_c0_model(&self) -> &'static C0Model {
        self.c0_models
            .iter()
            .find(|m| m.name == self.c0_default)
            .expect("generated default c0 model is among the models")
    }
}

/// The kind of lattice a discretisation starts from (a scene's `lattice`,
/// by name; the paper's by default): described once, in the crate
/// `shearsph-lattice` (`lattice/`), which the generator reads too;
/// `generated/` names it here as `Lattice::Triangular`.
pub use shearsph_lattice::Lattice;

/// Where the c0 models of a discretisation were derived: the configuration
/// where the search found the maximum compaction.
#[derive(Debug, Clone, Copy)]
pub struct C0Configuration {
    /// t / T of the configuration (exact when symmetric).
    pub t: Derived,
    /// eps0 = eps there.
    pub eps0: Derived,
    /// `true` at a symmetric configuration (t = 0 or 0.5 T: exact
    /// coefficients); `false` elsewhere (coefficients to stated high precision).
    pub symmetric: bool,
    /// For the reader.
    pub label: &'static str,
}

/// A c0 model that has no c0 on a discretisation, and the fact why.
#[derive(Debug, Clone, Copy)]
pub struct NoC0 {
    pub model: &'static str,
    /// e.g. "no c0: the gradient W' vanishes at every neighbour in reach ...".
    pub fact: &'static str,
}

/// What [`eps_at`] needs of a discretisation.
#[derive(Debug, Clone, Copy)]
pub struct EpsLattice {
    /// The lattice: row k's phase at t = 0 is `lattice.offset(k)` (in d).
    pub lattice: Lattice,
    /// The rows in reach: k = -layers..=layers.
    pub layers: i32,
    /// dy^2 in d^2 (the kind's exact `dy2`, 3/4 on the triangular lattice):
    /// row k is at y^2 = k^2 dy^2.
    pub dy2: f64,
    /// Particles a = -reach..=reach of each row are summed (in d).
    pub reach: i32,
    /// (d/h)^2: q^2 = r^2 (d/h)^2.
    pub inv_h2: f64,
    /// The particle area m/rho0 in h^2: dy d / h^2.
    pub area: f64,
}

/// eps(t, n) = rho/rho0 - 1 for a particle of layer n under the ideal
/// shear (7), t as a fraction of T = d N^2 / U; `walls = Some(N)` for fixed
/// walls at |j| >= N, `None` for an interior particle. Layer j = n + k moves
/// by (n^2 - j^2) t d relative to the particle, a wall layer by (n^2 - N^2) t d.
#[inline]
pub fn eps_at<K: Kernel>(lat: &EpsLattice, t: f64, n: u32, walls: Option<u32>) -> f64 {
    let n = n as f64;
    let walls = walls.map(|nl| nl as f64);
    let row = |phase: f64, y2: f64| -> f64 {
        let phase = phase - phase.floor();
        let mut sum = 0.0;
        for a in -lat.reach..=lat.reach {
            let x = a as f64 + phase;
            sum += K::w((x * x + y2) * lat.inv_h2);
        }
        sum
    };
    let mut sum = 0.0;
    for k in -lat.layers..=lat.layers {
        let kf = f64::from(k);
        // exact: k^2 dy^2 has few bits, the phase is 0 or 1/2
        let (phase0, y2) = (lat.lattice.offset(k), kf * kf * lat.dy2);
        if k == 0 {
            // the own layer never moves relative to the particle
            sum += row(phase0, y2);
            continue;
        }
        let j = n + kf;
        let speed = match walls {
            Some(nl) if j.abs() >= nl => n * n - nl * nl,
            _ => n * n - j * j,
        };
        sum += row(phase0 + speed * t, y2);
    }
    lat.area * sum - 1.0
}

/// [`eps_at`] on discretisation `I` of kernel `K` (`K::INFO.discretisations[I]`):
/// the one function every emitted `DiscretisationInfo::eps_at` points to.
pub fn eps_at_disc<K: Kernel, const I: usize>(t: f64, n: u32, walls: Option<u32>) -> f64 {
    eps_at::<K>(&K::INFO.discretisations[I].eps_lattice, t, n, walls)
}

/// Everything the generator derived for a kernel on one discretisation.
#[derive(Debug, Clone, Copy)]
pub struct DiscretisationInfo {
    pub lattice: Lattice,
    /// h/d, and its exact form ("13/10").
    pub h_over_d: f64,
    pub h_over_d_exact: &'static str,
    /// Layer spacing dy in d (sqrt(3)/2 on the triangular lattice).
    pub dy: f64,
    /// Compaction of a centre particle (n = 0) on this discretisation.
    pub eps: EpsInfo,
    /// Where the c0 models were derived.
    pub c0_configuration: C0Configuration,
    /// The models that have a c0 here (a != 0); the others are in `no_c0`.
    pub c0_models: &'static [C0Model],
    pub no_c0: &'static [NoC0],
    /// The rows of eps(t, n); `eps_at` evaluates them.
    pub eps_lattice: EpsLattice,
    /// eps(t, n) on this discretisation: [`eps_at_disc`] for the kernel and
    /// this entry's index.
    pub eps_at: fn(t: f64, n: u32, walls: Option<u32>) -> f64,
}

impl DiscretisationInfo {
    /// "square, h = 13/10 d": how figures and tables name it.
    pub fn label(&self) -> String {
        format!("{}, h = {} d", self.lattice.name(), self.h_over_d_exact)
    }
    /// The paper's: triangular, h = d.
    pub fn is_papers(&self) -> bool {
        self.lattice == Lattice::Triangular && self.h_over_d_exact == "1"
    }
    /// The model called `name`'s fact when it has no c0 here.
    pub fn no_c0_fact(&self, name: &str) -> Option<&'static str> {
        self.no_c0.iter().find(|m| m.model == name).map(|m| m.fact)
    }
    pub fn c0_model(&self, name: &str) -> Option<&'static C0Model> {
        self.c0_models.iter().find(|m| m.name == name)
    }
}

/// Runs a function generic over the kernel for a kernel chosen by name at
/// run time; implemented by callers, dispatched by the generated registry
/// (`generated::with_kernel`), so adding a kernel needs no hand edit.
pub trait KernelVisitor {
    type Output;
    fn visit<K: Kernel>(self) -> Self::Output;
}
