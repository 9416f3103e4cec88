//! Which input to name when a derived quantity or the run's cost is out of
//! bounds: the error says the field the user set, not the intermediate
//! number that overflowed.

use super::channel::Channel;
use super::cost;
use crate::analytic::Poiseuille;
use crate::config::{invalid, C0Spec, Scene, SceneError};
use crate::format::fmt_value;

/// A run estimated to take more than a year on one core: no bound anyone
/// would raise `max_run_s` to, so the input that made it that long is
/// named instead (see [`blame_run_time`]).
pub const IMPLAUSIBLE_RUN_S: f64 = 365.25 * 86400.0;

/// The run-time guard's error `e`, naming the input that made the run too
/// long when no plausible bound would let it run: above
/// [`IMPLAUSIBLE_RUN_S`], of the inputs the scene set that the estimate
/// grows with (t_end, c0, n_layers, re or p, u, d, h_over_d, skin), the one
/// farthest from its built-in default (t_end from the start-up's decay
/// time, c0 from 10 U), if at least ten times off it. Otherwise (a run of
/// days: raise the bound, or shorten it) `e` as it is, naming `max_run_s`.
pub(super) fn blame_run_time(
    e: SceneError,
    scene: &Scene,
    channel: &Channel,
    c0: f64,
    t_end: f64,
    support: f64,
) -> SceneError {
    let est = cost::Estimate::new(channel, c0, t_end).seconds(channel, support, scene.skin);
    if est <= IMPLAUSIBLE_RUN_S {
        return e;
    }
    let builtin = Scene::builtin();
    let mut candidates: Vec<(&'static str, f64)> = Vec::new();
    if let Some(t) = scene.t_end {
        candidates.push(("t_end", t / channel.flow.decay_time(builtin.decay_tol)));
    }
    match scene.c0 {
        C0Spec::Value(v) => candidates.push(("c0", v / (10.0 * scene.u))),
        C0Spec::Rule { factor, .. } => candidates.push(("c0", factor)),
    }
    candidates.push((
        "n_layers",
        f64::from(scene.n_layers) / f64::from(builtin.n_layers),
    ));
    match (scene.re, scene.p) {
        (Some(re), _) => candidates.push(("re", re / builtin.re.unwrap_or(10.0))),
        // p against the body force the built-in Re gives this channel.
        (None, Some(p)) => {
            let p_builtin =
                Poiseuille::from_re(scene.u, channel.flow.b, builtin.re.unwrap_or(10.0)).p;
            candidates.push(("p", p / p_builtin.max(f64::MIN_POSITIVE)))
        }
        _ => {}
    }
    for (field, v, d) in [
        ("u", scene.u, builtin.u),
        ("d", scene.d, builtin.d),
        ("h_over_d", scene.h_over_d, builtin.h_over_d),
        ("skin", scene.skin, builtin.skin),
    ] {
        candidates.push((field, v / d));
    }
    let off = |r: f64| {
        if r > 0.0 && r.is_finite() {
            r.ln().abs()
        } else {
            0.0
        }
    };
    let Some((field, ratio)) = candidates
        .into_iter()
        .filter(|(_, r)| off(*r) >= 10f64.ln())
        .max_by(|a, b| off(a.1).total_cmp(&off(b.1)))
    else {
        return e;
    };
    let value = match field {
        "t_end" => t_end,
        "c0" => c0,
        "n_layers" => f64::from(scene.n_layers),
        "re" => scene.re.unwrap_or(f64::NAN),
        "p" => scene.p.unwrap_or(f64::NAN),
        "u" => scene.u,
        "d" => scene.d,
        "h_over_d" => scene.h_over_d,
        _ => scene.skin,
    };
    let message = match &e {
        SceneError::Invalid { message, .. } => message.clone(),
        other => other.to_string(),
    };
    invalid(
        field,
        format!(
            "{} (the input farthest from its default, {:.0e} times it) makes the run far too long \
             for any bound: {}; bring {field} nearer its default",
            fmt_value(value),
            ratio,
            message.split("; raise it").next().unwrap_or(&message)
        ),
    )
}

/// `a` and then those of `b` not in it: the inputs of a quantity derived
/// from others.
pub(crate) fn with(
    a: &[(&'static str, f64)],
    b: &[(&'static str, f64)],
) -> Vec<(&'static str, f64)> {
    let mut v = a.to_vec();
    v.extend(b.iter().filter(|(f, _)| !a.iter().any(|(g, _)| g == f)));
    v
}

/// c0 as the inputs of a quantity derived from it: c0 itself when the
/// scene gives its value; when a rule gives it, what the scene gave: U
/// (every rule scales c0 with it), Re or p (the derived rules depend on
/// them; of the flow's inputs `flow_in`, all but d), and the rule's factor
/// if not 1 (named `c0`, the field that holds it). So an extreme c0 is
/// blamed on the field that made it.
pub(super) fn c0_inputs(
    scene: &Scene,
    c0: f64,
    flow_in: &[(&'static str, f64)],
) -> Vec<(&'static str, f64)> {
    let flow = || flow_in.iter().filter(|(f, _)| *f != "d").copied();
    match scene.c0 {
        C0Spec::Value(_) => vec![("c0", c0)],
        C0Spec::Rule { factor, .. } if factor != 1.0 => flow().chain([("c0", factor)]).collect(),
        C0Spec::Rule { .. } => flow().collect(),
    }
}

/// Err unless the derived quantity `name` is a finite positive number. The
/// error names the input that made it so: of the inputs it was computed
/// from (`(field, value)`), the one farthest from 1 in magnitude (an input
/// of 1e300 or 1e-300 is what overflows or underflows), and lists the rest.
pub(crate) fn derived(
    name: &str,
    value: f64,
    inputs: &[(&'static str, f64)],
) -> Result<(), SceneError> {
    // Normal, not only positive: a subnormal (below 2.2e-308) has lost its
    // precision, and its square is 0.
    if value > 0.0 && value.is_normal() {
        return Ok(());
    }
    let extremity = |v: f64| {
        if v == 0.0 || !v.is_finite() {
            f64::INFINITY
        } else {
            v.abs().ln().abs()
        }
    };
    let (field, v) = inputs
        .iter()
        .copied()
        .fold(("d", f64::NEG_INFINITY), |best, (f, v)| {
            if extremity(v) > best.1 {
                (f, extremity(v))
            } else {
                best
            }
        });
    let given = inputs
        .iter()
        .map(|(f, v)| format!("{f} = {}", fmt_value(*v)))
        .collect::<Vec<_>>()
        .join(", ");
    let value_of = inputs
        .iter()
        .find(|(f, _)| *f == field)
        .map_or(v, |(_, v)| *v);
    Err(invalid(
        field,
        format!(
            "{} makes {name} = {}, not a finite positive number (it comes from {given}); bring \
             {field} nearer the others' scale",
            fmt_value(value_of),
            fmt_value(value)
        ),
    ))
}
