//! The leapfrog's first half: kick and drift, with the displacement the
//! neighbour list checks (the closing kick is in [`super::forces`]).

use rayon::prelude::*;

use super::isa::Isa;
use super::state::State;
use super::CHUNK;
use crate::solver::neighbours::Displacements;

/// First half of the leapfrog: v += dt/2 a, x += dt v, and the prediction
/// v + dt/2 a of the end-of-step velocity for the forces. Fills `motion`
/// with each block's displacements since the last rebuild, from the shear
/// reference (x0 + u_ref since, y0; `since` the time from the rebuild to
/// the drift's end) or, without one (`None`: a lattice that keeps its
/// order), from (x0, y0), and how far from the centre line it reached.
/// Parallel over tasks of whole blocks (a block, one lattice layer, is
/// only a few particles).
pub(crate) fn kick_drift(
    s: &mut State,
    dt: f64,
    since: Option<f64>,
    block: usize,
    motion: &mut Vec<(Displacements, f64)>,
) {
    let nf = s.n_fluid;
    let half = 0.5 * dt;
    // Sized once: every later step reuses it.
    motion.resize(nf / block, (Displacements::EMPTY, 0.0));
    let blocks_per_task = CHUNK.div_ceil(block);
    let span = blocks_per_task * block;
    let isa = Isa::detect();
    (
        (
            s.x[..nf].par_chunks_mut(span),
            s.y[..nf].par_chunks_mut(span),
            s.vx[..nf].par_chunks_mut(span),
            s.vy[..nf].par_chunks_mut(span),
            s.v_pred_x[..nf].par_chunks_mut(span),
            s.v_pred_y[..nf].par_chunks_mut(span),
        ),
        (
            s.ax.par_chunks(span),
            s.ay.par_chunks(span),
            s.x0.par_chunks(span),
            s.y0.par_chunks(span),
            s.u_ref.par_chunks(span),
        ),
        motion.par_chunks_mut(blocks_per_task),
    )
        .into_par_iter()
        .for_each(|(out, input, motion)| match since {
            Some(since) => {
                kick_drift_task_on::<true>(isa, (half, dt, since), block, out, input, motion)
            }
            None => kick_drift_task_on::<false>(isa, (half, dt, 0.0), block, out, input, motion),
        });
}

/// One task's state that the kick and drift update: x, y, v_x, v_y and
/// the predicted v_x, v_y.
type Moving<'a> = (
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
);

/// What it reads: a_x, a_y, the positions at the last rebuild and the
/// shear reference's speeds.
type Fixed<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a [f64], &'a [f64]);

/// The kick and drift of one task's whole blocks, and each block's
/// displacement box (from the shear reference with `REFERENCE`) and
/// largest |y|.
#[inline(always)]
fn kick_drift_task<const REFERENCE: bool>(
    (half, dt, since): (f64, f64, f64),
    block: usize,
    (x, y, vx, vy, v_pred_x, v_pred_y): Moving,
    (ax, ay, x0, y0, u_ref): Fixed,
    motion: &mut [(Displacements, f64)],
) {
    for (b, m) in motion.iter_mut().enumerate() {
        let r = b * block..(b + 1) * block;
        let (x, y, vx, vy) = (
            &mut x[r.clone()],
            &mut y[r.clone()],
            &mut vx[r.clone()],
            &mut vy[r.clone()],
        );
        let (v_pred_x, v_pred_y) = (&mut v_pred_x[r.clone()], &mut v_pred_y[r.clone()]);
        let (ax, ay) = (&ax[r.clone()], &ay[r.clone()]);
        let (x0, y0, u_ref) = (&x0[r.clone()], &y0[r.clone()], &u_ref[r]);
        let mut d = Displacements::EMPTY;
        let mut max_abs_y = 0.0f64;
        for k in 0..block {
            vx[k] += half * ax[k];
            vy[k] += half * ay[k];
            x[k] += dt * vx[k];
            y[k] += dt * vy[k];
            v_pred_x[k] = vx[k] + half * ax[k];
            v_pred_y[k] = vy[k] + half * ay[k];
            let dx = x[k] - x0[k];
            d.add(
                if REFERENCE { dx - u_ref[k] * since } else { dx },
                y[k] - y0[k],
            );
            // NaN compares false: make it count as out of the channel.
            let ya = y[k].abs();
            max_abs_y = if ya.is_nan() {
                f64::INFINITY
            } else {
                max_abs_y.max(ya)
            };
        }
        *m = (d, max_abs_y);
    }
}

on_isa! {
    /// [`kick_drift_task`] compiled for the instruction set `isa`.
    fn kick_drift_task_on[const REFERENCE: bool] => kick_drift_task[REFERENCE](
        steps: (f64, f64, f64),
        block: usize,
        out: Moving,
        input: Fixed,
        motion: &mut [(Displacements, f64)]
    )
}
