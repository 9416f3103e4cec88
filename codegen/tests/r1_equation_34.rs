//! For R = 1 the general lattice-sum construction must give (34) term by term:
//!
//! ```text
//! (2 (c0^2 eps0 + p d)/(1 + eps0) + alpha c0 U/(2 N^2)) W'(d)
//!   - p d/(1 + eps0) (3/sqrt 3) W'(sqrt(3)/2 d) = 0,
//! ```
//!
//! i.e. times (1 + eps0): a = 2 eps0 W'(1), b = (1 + eps0) W'(1)/2,
//! c = 2 W'(1) - sqrt(3) W'(sqrt(3)/2).

use rug::Rational;
use shearsph_codegen::analysis::{analyse, Options};
use shearsph_codegen::exact::Exact;
use shearsph_codegen::kernel::parse_kernel;
use std::path::Path;

#[test]
fn composite_reproduces_equation_34_for_every_model() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels/composite.toml");
    let src = std::fs::read_to_string(&path).unwrap();
    let def = parse_kernel(&path, &src).unwrap();
    let a = analyse(
        &def,
        &[],
        Options {
            digits: 30,
            check_layers: 6,
        },
    );
    let dw1 = def.dw.eval_q2(&Rational::from(1));
    let dw_s = def.dw.eval_q2(&Rational::from((3, 4)));
    let eps0 = a.paper().eps.half_period.exact.clone().unwrap();
    let one_eps = &Exact::one() + &eps0;
    let sqrt3 = Exact::sqrt_rational(&Rational::from(3));
    let want_a = &(&Exact::int(2) * &eps0) * &dw1;
    let want_b = &(&one_eps * &dw1) * &Exact::rational(Rational::from((1, 2)));
    let want_c = &(&Exact::int(2) * &dw1) - &(&sqrt3 * &dw_s);
    for m in a.paper().exact_models() {
        assert_eq!(m.a, want_a, "a, model {}", m.model.name);
        assert_eq!(m.b, want_b, "b, model {}", m.model.name);
        assert_eq!(m.c, want_c, "c, model {}", m.model.name);
    }
    // and the terms (26), (29), (32) separately, in the paper's sign conventions:
    // dP/dx(0) = -m p G(0) = -3 m p W'(d); M u''(0) = -(3/2) p m V(0) = -3 p m W'(d);
    // Pi(0) = alpha c0 (U/N^2) m Av(0) = (1/2) alpha c0 (U/N^2) m W'(d)
    assert_eq!(a.paper().sums_t0.g, &Exact::int(3) * &dw1);
    assert_eq!(
        &Exact::rational(Rational::from((3, 2))) * &a.paper().sums_t0.v,
        &Exact::int(3) * &dw1
    );
    assert_eq!(
        a.paper().sums_t0.av,
        &Exact::rational(Rational::from((1, 2))) * &dw1
    );
    // (28): only the own layer's pair at x = -d, d has an x offset at 0.5 T
    assert_eq!(a.paper().sums_half.g, &Exact::int(2) * &dw1);
    // (30): -(3/2) p m V(0.5T)/(1+eps0) with V = W'(sqrt3/2)/(sqrt3/2) = (2/sqrt 3) W'
    let v_half = (&Exact::int(2) * &dw_s).div_monomial(&sqrt3).unwrap();
    assert_eq!(a.paper().sums_half.v, v_half);
    assert!(
        a.paper().sums_half.av.is_zero(),
        "Pi(0.5T) = 0 by geometry for R = 1"
    );
}
