//! Accelerations (pressure (12) with the artificial viscosity (31), the
//! viscous Laplacian (14), the body force) and the closing kick.

use rayon::prelude::*;

use super::density::GForm;
use super::isa::{lane_sum, Isa};
use super::state::{Params, State};
use super::CHUNK;
use crate::solver::neighbours::{NeighbourList, Window, LANES};

/// What the force pass saw at the end of the step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Forces {
    /// Largest |v| and |a| of the fluid.
    pub v_max: f64,
    pub a_max: f64,
    /// false when any velocity or acceleration is NaN or infinite.
    pub finite: bool,
}

impl Forces {
    const NONE: Forces = Forces {
        v_max: 0.0,
        a_max: 0.0,
        finite: true,
    };

    fn merge(self, o: Forces) -> Forces {
        Forces {
            v_max: self.v_max.max(o.v_max),
            a_max: self.a_max.max(o.a_max),
            finite: self.finite && o.finite,
        }
    }
}

/// Floating-point operations per pair in the force pass's loop (the kernel
/// was evaluated in the density pass): dx with its image, dy (3), p_ij (1),
/// v_ij (2), the pressure and Laplacian terms of both components, scaled per
/// particle, summed and times (dW/dq)/q (10), the two lane sums (2). With
/// artificial viscosity also r^2 (3), v_ij . r_ij (3), its min, division and
/// scale (3), its two terms (4).
pub(crate) const FORCE_PAIR_FLOPS: u32 = 18;
pub(crate) const FORCE_PAIR_FLOPS_AV: u32 = FORCE_PAIR_FLOPS + 13;
/// Mirrored walls add the factor beta: a product, a min and a sum (3), and
/// its product with the viscous scale (1).
pub(crate) const FORCE_PAIR_FLOPS_MIRROR: u32 = 4;

/// The particle-level factors of the force terms.
#[derive(Clone, Copy)]
pub(super) struct Scales {
    /// m / rho_i^2 (paper) or m (symmetric).
    pressure: f64,
    /// alpha c0 h m / rho_i.
    av: f64,
    /// 2 mu / rho_i.
    visc: f64,
    /// 1 / (B - |y_i|), the inverse distance to the no-slip plane, with
    /// mirrored walls; 0 without (the factor is then 1).
    inv_gap: f64,
    /// The largest factor beta of mirrored walls ([`Params::beta_max`]).
    beta_max: f64,
}

/// One particle's force inputs.
#[derive(Clone, Copy)]
pub(super) struct ForceArgs<'a> {
    /// The particle.
    pub i: usize,
    /// Its list as windows of consecutive indices.
    pub windows: &'a [Window],
    /// The windows' lanes' (dW/dq)/q ([`WindowG`]).
    pub g: WindowG<'a>,
    /// Positions (x, y).
    pub xs: (&'a [f64], &'a [f64]),
    /// Velocities (vx, vy) predicted at the step's end.
    pub vs: (&'a [f64], &'a [f64]),
    /// P (paper form) or P/rho^2 (symmetric).
    pub pressure_term: &'a [f64],
    /// m/rho.
    pub vol: &'a [f64],
    /// Wall depth (mirrored walls only).
    pub depth: &'a [f64],
    /// The strip's width, for the images' offsets.
    pub width: f64,
    pub scales: Scales,
}

/// Where the force pass finds a particle's windows' (dW/dq)/q
/// ([`NeighbourList::lane_table`]): LANES a window in the window-lane
/// table (0 in a lane not listed), or gathered from the pair table through
/// each window's sources (the zero place for a lane not listed).
#[derive(Clone, Copy)]
pub(super) enum WindowG<'a> {
    Lanes(&'a [f64]),
    Gather {
        sources: &'a [[u32; LANES]],
        pair_g: &'a [f64],
    },
}

/// LANES consecutive values from `start`: one contiguous load.
#[inline(always)]
fn lanes(v: &[f64], start: usize) -> &[f64; LANES] {
    v[start..start + LANES]
        .try_into()
        .expect("a window's particles exist")
}

/// Particle i's values in [`pair_forces`].
struct ParticleValues {
    xi: f64,
    yi: f64,
    vxi: f64,
    vyi: f64,
    pqi: f64,
    scales: Scales,
    beta_cap: f64,
}

/// One window's values in [`pair_forces`]: its particles' as LANES
/// consecutive values, and its lanes' (dW/dq)/q.
struct WindowValues<'a> {
    xw: &'a [f64; LANES],
    yw: &'a [f64; LANES],
    vxw: &'a [f64; LANES],
    vyw: &'a [f64; LANES],
    pqw: &'a [f64; LANES],
    volw: &'a [f64; LANES],
    depthw: &'a [f64; LANES],
    g: [f64; LANES],
}

/// One window's terms added into its lanes' accumulators ([`pair_forces`]),
/// lane l's neighbour seen through the image at x offset `offset(l)`.
#[inline(always)]
fn window_terms<const AV: bool, const MIRROR: bool>(
    particle: &ParticleValues,
    window: &WindowValues,
    offset: impl Fn(usize) -> f64,
    acc_x: &mut [f64; LANES],
    acc_y: &mut [f64; LANES],
) {
    let ParticleValues {
        xi,
        yi,
        vxi,
        vyi,
        pqi,
        scales,
        beta_cap,
    } = *particle;
    let WindowValues {
        xw,
        yw,
        vxw,
        vyw,
        pqw,
        volw,
        depthw,
        g,
    } = *window;
    for l in 0..LANES {
        let g = g[l];
        // grad_i W_ij = g r_ij, up to the h^-4 applied at the end.
        let dx = xi - xw[l] + offset(l);
        let dy = yi - yw[l];
        let p = scales.pressure * (pqi + pqw[l]);
        let (dvx, dvy) = (vxi - vxw[l], vyi - vyw[l]);
        let mut lv = scales.visc * volw[l];
        if MIRROR {
            // A wall particle at depth D beyond the no-slip plane shows
            // fluid particle i, at distance g from it, the velocity
            // -(D / g) v_i: the velocity difference grows by beta.
            // A select, not f64::min: the cap is not NaN (beta_max >=
            // 1), and min's care for a NaN cap costs two instructions a
            // lane. The same value for every ratio, NaN included.
            let ratio = depthw[l] * scales.inv_gap;
            lv *= 1.0 + if ratio < beta_cap { ratio } else { beta_cap };
        }
        let (mut fx, mut fy) = (lv * dvx - p * dx, lv * dvy - p * dy);
        if AV {
            // Only approaching pairs (v_ij . r_ij < 0), branch-free.
            let r2 = dx * dx + dy * dy;
            let vr = dvx * dx + dvy * dy;
            // r^2 > 0 for every listed pair; the floor keeps the term
            // 0, not NaN, in a lane that is not listed and holds i
            // itself (g = 0 there).
            let a = scales.av * (vr.min(0.0) / r2.max(f64::MIN_POSITIVE));
            fx += a * dx;
            fy += a * dy;
        }
        acc_x[l] += fx * g;
        acc_y[l] += fy * g;
    }
}

/// The particle i's (sum_x, sum_y) of its force terms, up to h^-4: one
/// loop over its windows ([`Window`]), each window's particle values
/// loaded as contiguous vectors (no gather) and its (dW/dq)/q so too from
/// the window-lane table, or (`GATHER`, [`WindowG::Gather`]) gathered from
/// the pair table: the same values either way. Each lane's term is added
/// into its lane's accumulator, without branches or bounds checks in the
/// lanes. A lane not listed has g = 0 and adds 0: its terms are finite
/// for a finite state (the artificial viscosity's r^2 has a floor). A
/// state that is not finite fails the run at this step anyway
/// ([`Forces::finite`]).
#[inline(always)]
pub(super) fn pair_forces<const AV: bool, const MIRROR: bool, const GATHER: bool>(
    args: ForceArgs,
) -> (f64, f64) {
    let ForceArgs {
        i,
        windows,
        g,
        xs,
        vs,
        pressure_term,
        vol,
        depth,
        width,
        scales,
    } = args;
    let (x, y) = xs;
    let (v_pred_x, v_pred_y) = vs;
    let n = x.len();
    assert!(n > i && y.len() == n && v_pred_x.len() == n && v_pred_y.len() == n);
    assert!(pressure_term.len() == n && vol.len() == n && (!MIRROR || depth.len() == n));
    let (lane_g, sources, pair_g) = match g {
        WindowG::Lanes(lane_g) => (lane_g, &[][..], &[0.0][..]),
        WindowG::Gather { sources, pair_g } => (&[][..], sources, pair_g),
    };
    assert!(GATHER == matches!(g, WindowG::Gather { .. }));
    assert!(GATHER || lane_g.len() == windows.len() * LANES);
    assert!(!GATHER || (sources.len() == windows.len() && !pair_g.is_empty()));
    // Clamped in 32 bits: a vector gather, no bounds check (a source is in
    // the table by construction of the list anyway).
    let last = u32::try_from(pair_g.len() - 1).expect("slots fit in u32");
    let (xi, yi, vxi, vyi, pqi) = (x[i], y[i], v_pred_x[i], v_pred_y[i], pressure_term[i]);
    let particle = ParticleValues {
        xi,
        yi,
        vxi,
        vyi,
        pqi,
        scales,
        beta_cap: scales.beta_max - 1.0,
    };
    let mut acc_x = [0.0; LANES];
    let mut acc_y = [0.0; LANES];
    for (k, win) in windows.iter().enumerate() {
        let g: [f64; LANES] = if GATHER {
            let src = &sources[k];
            std::array::from_fn(|l| pair_g[src[l].min(last) as usize])
        } else {
            *lanes(lane_g, k * LANES)
        };
        let start = win.start as usize;
        let (xw, yw) = (lanes(x, start), lanes(y, start));
        let (vxw, vyw) = (lanes(v_pred_x, start), lanes(v_pred_y, start));
        let (pqw, volw) = (lanes(pressure_term, start), lanes(vol, start));
        let depthw = if MIRROR { lanes(depth, start) } else { xw };
        // A window whose every lane has g = 0 (its pairs out of the
        // kernel's support this step: listed for the skin, or at R h
        // exactly; on a square lattice at h = d a row or two of every
        // list) adds +-0 to every accumulator, which leaves it as it is
        // (an accumulator is never -0: it starts at +0, and a sum that
        // cancels to zero rounds to +0): skipped, the same bits. (Terms
        // that are not finite would have made i's sum NaN; such a state
        // fails the run through the particle that holds it anyway,
        // [`Forces::finite`].)
        if g.iter().all(|&g| g == 0.0) {
            continue;
        }
        // Most windows hold no lane found through an image (only lists near
        // the strip's edges wrap): every offset is then (1 - 1) width = +0,
        // and such a window adds +0 to each lane's dx without converting the
        // lanes' codes, the same values: the same bits. The lanes are one
        // function, inlined into both arms: an array of offsets chosen per
        // window instead left the loop without artificial viscosity in
        // 2-lane code (docs/performance.md, the offsets of a window).
        let window = WindowValues {
            xw,
            yw,
            vxw,
            vyw,
            pqw,
            volw,
            depthw,
            g,
        };
        if win.unshifted() {
            window_terms::<AV, MIRROR>(&particle, &window, |_| 0.0, &mut acc_x, &mut acc_y);
        } else {
            window_terms::<AV, MIRROR>(
                &particle,
                &window,
                |l| win.offset(l, width),
                &mut acc_x,
                &mut acc_y,
            );
        }
    }
    (lane_sum(acc_x), lane_sum(acc_y))
}

/// Accelerations of the fluid, then the closing kick v += dt/2 a, over the
/// listed pairs with the (dW/dq)/q that [`super::density::kernel_pass`]
/// left in the window lanes or the pair table (0 out of reach, [`GForm`]).
///
/// - pressure (12): -(m / rho_i^2) sum (P_i + P_j) grad_i W_ij, or the
///   symmetric -m sum (P_i / rho_i^2 + P_j / rho_j^2) grad_i W_ij;
/// - artificial viscosity (31): (alpha c0 h m / rho_i) sum over approaching
///   pairs of (v_ij . r_ij) / r_ij^2 grad_i W_ij, repulsive;
/// - viscosity, the Laplacian (14) with the right sign on both components:
///   (2 mu m / rho_i) sum (v_i - v_j) / rho_j (dW/dr) / r_ij; with mirrored
///   walls (Morris, Fox and Zhu 1997), a wall particle j at depth D_j beyond
///   the no-slip plane shows fluid particle i, at distance g_i from it, the
///   velocity -(D_j / g_i) v_i, so v_i - v_j = beta v_i with
///   beta = min(1 + D_j / g_i, beta_max) ([`Params::beta_max`]);
/// - the body force p along +x.
///
/// Compiled for `isa`.
pub(crate) fn forces(
    s: &mut State,
    list: &NeighbourList,
    params: &Params,
    half_dt: f64,
    isa: Isa,
) -> Forces {
    forces_in_tiles(s, list, params, half_dt, isa, FORCE_TILE)
}

/// Particles of a lattice layer's stretch along x that the force pass
/// visits together, at least ([`forces_in_tiles`]): a disordered fluid
/// whose layers hold two such tiles or more (from 1.7e5-2e5 particles on
/// the bench's channel) is visited tile by tile. On the bench's disordered
/// scene at 1e6 particles, on the project's 2-core Zen 4, 1.02-1.49x as
/// fast as in storage order on one thread (Morris's kernel the most, whose
/// force pass reads four bands above and below); 2048 and 8192 ran within
/// a few per cent of 4096 there, and tiles of 128 keyed by a task's place
/// in its layer rather than by x lost at 1e5 (docs/performance.md, the
/// force pass in tiles).
pub(crate) const FORCE_TILE: usize = 4096;

/// [`forces`], a disordered fluid visited in tiles of `tile` particles of
/// a layer along x where a layer holds two or more: each thread's share
/// of the tasks (CHUNK consecutive particles each) in storage order,
/// ordered within by the tile their first particle's x is in, then by
/// index. A disordered fluid's bands ([`State::reorder`]) are each stored
/// by x, so a tile's tasks are the same stretch of x in every band of the
/// share, and a neighbour's values and pair-table entries, read again by
/// the next bands' particles, are still in the last-level cache; in
/// storage order, a pass over bands longer than that cache reads them from
/// memory once a band. The shares keep each thread on what the passes
/// before this one left in its core's cache (tiles across the whole fluid
/// ran 0.82-0.92x on two threads at 2e5 particles). A lattice keeps
/// storage order: its rows stream, and tiles gained nothing on it. Each
/// particle's sums are its own, and the tasks' results are merged by
/// maxima and a conjunction: the order changes no result, the same bits.
pub(crate) fn forces_in_tiles(
    s: &mut State,
    list: &NeighbourList,
    params: &Params,
    half_dt: f64,
    isa: Isa,
    tile: usize,
) -> Forces {
    // The pressure form, the artificial viscosity and the walls' factor as
    // constants of the pair loop: each combination compiles to its own loop.
    // Without the artificial viscosity, walls that are not mirrored take the
    // loop with the factor too, at beta = 1 (`inv_gap` 0 in
    // `forces_chunk`): the same bits, and vector lanes, where LLVM leaves the
    // loop without both terms in scalar code (its cost model, it seems,
    // finds too little work a lane to pay for the gather of (dW/dq)/q):
    // 1.6x the whole run on one thread (measured with `shearsph bench`).
    let mirror = params.mirror_walls || !params.has_av;
    // Where the kernel pass left (dW/dq)/q for this list (checked in
    // `forces_with`).
    let gather = s.g_written.1 == GForm::Gather;
    let f = if params.symmetric {
        with_av::<true>(params.has_av, mirror, gather)
    } else {
        with_av::<false>(params.has_av, mirror, gather)
    };
    f(s, list, params, half_dt, isa, tile)
}

/// The force pass with its flags as constants.
type ForcesFn = fn(&mut State, &NeighbourList, &Params, f64, Isa, usize) -> Forces;

/// The flags made constants one at a time, each level two arms: a new flag
/// is one more level, not twice the table.
fn with_av<const SYMMETRIC: bool>(av: bool, mirror: bool, gather: bool) -> ForcesFn {
    if av {
        with_mirror::<SYMMETRIC, true>(mirror, gather)
    } else {
        with_mirror::<SYMMETRIC, false>(mirror, gather)
    }
}

fn with_mirror<const SYMMETRIC: bool, const AV: bool>(mirror: bool, gather: bool) -> ForcesFn {
    if mirror {
        with_gather::<SYMMETRIC, AV, true>(gather)
    } else {
        with_gather::<SYMMETRIC, AV, false>(gather)
    }
}

fn with_gather<const SYMMETRIC: bool, const AV: bool, const MIRROR: bool>(
    gather: bool,
) -> ForcesFn {
    if gather {
        forces_with::<SYMMETRIC, AV, MIRROR, true>
    } else {
        forces_with::<SYMMETRIC, AV, MIRROR, false>
    }
}

pub(super) fn forces_with<
    const SYMMETRIC: bool,
    const AV: bool,
    const MIRROR: bool,
    const GATHER: bool,
>(
    s: &mut State,
    list: &NeighbourList,
    params: &Params,
    half_dt: f64,
    isa: Isa,
    tile: usize,
) -> Forces {
    let form = if GATHER { GForm::Gather } else { GForm::Lanes };
    assert_eq!(
        s.g_written,
        (list.generation(), form),
        "the kernel pass ran on this list, in this form"
    );
    let nf = s.n_fluid;
    let n = s.x.len();
    let (x, y, v_pred_x, v_pred_y) = (&s.x[..n], &s.y[..n], &s.v_pred_x[..n], &s.v_pred_y[..n]);
    let (rho, vol, depth) = (&s.rho[..n], &s.vol[..n], &s.depth[..n]);
    let pressure_term = if SYMMETRIC {
        &s.p_rho2[..n]
    } else {
        &s.press[..n]
    };
    let input = ForcesIn {
        x,
        y,
        v_pred_x,
        v_pred_y,
        rho,
        vol,
        depth,
        pressure_term,
        g: if GATHER {
            WindowG::Gather {
                sources: &[],
                pair_g: &s.pair_g,
            }
        } else {
            WindowG::Lanes(&s.lane_g)
        },
        list,
        width: list.width(),
        params,
        half_dt,
    };
    let task = |(c, out)| forces_chunk_on::<SYMMETRIC, AV, MIRROR, GATHER>(isa, c, out, &input);
    // As many tiles as hold `tile` particles of a layer each, at least;
    // a lattice's rows stream in storage order (measured: tiles gained
    // nothing on the ordered scenes).
    let tiles = list.block() / tile.max(1);
    if tiles < 2 || !list.disordered() {
        return (
            s.ax.par_chunks_mut(CHUNK),
            s.ay.par_chunks_mut(CHUNK),
            s.vx[..nf].par_chunks_mut(CHUNK),
            s.vy[..nf].par_chunks_mut(CHUNK),
        )
            .into_par_iter()
            .enumerate()
            .map(task)
            .reduce(|| Forces::NONE, Forces::merge);
    }
    // x may have left the strip since the rebuild, or be NaN: the key
    // only orders.
    let tile_width = list.width() / tiles as f64;
    let mut tasks: Vec<(usize, ForcesOut)> =
        s.ax.chunks_mut(CHUNK)
            .zip(s.ay.chunks_mut(CHUNK))
            .zip(s.vx[..nf].chunks_mut(CHUNK))
            .zip(s.vy[..nf].chunks_mut(CHUNK))
            .map(|(((ax, ay), vx), vy)| (ax, ay, vx, vy))
            .enumerate()
            .collect();
    // Each thread's share of the tasks in storage order, tiled within:
    // the passes before this one ran each thread over its share in
    // storage order, and left what this one reads in that core's cache.
    let share = tasks.len().div_ceil(rayon::current_num_threads().max(1));
    tasks.sort_by_key(|&(c, _)| (c / share, (x[c * CHUNK] / tile_width).floor() as i64, c));
    tasks
        .into_par_iter()
        .map(task)
        .reduce(|| Forces::NONE, Forces::merge)
}

/// What every task of the force pass reads.
pub(super) struct ForcesIn<'a> {
    x: &'a [f64],
    y: &'a [f64],
    v_pred_x: &'a [f64],
    v_pred_y: &'a [f64],
    rho: &'a [f64],
    vol: &'a [f64],
    depth: &'a [f64],
    /// P (paper form) or P / rho^2 (symmetric).
    pressure_term: &'a [f64],
    /// (dW/dq)/q of every window lane, or the pair table's to gather
    /// (each particle's sources taken from the list).
    g: WindowG<'a>,
    list: &'a NeighbourList,
    width: f64,
    params: &'a Params,
    half_dt: f64,
}

/// One task's outputs: ax, ay, vx, vy.
pub(super) type ForcesOut<'a> = (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// Accelerations and the closing kick for the fluid particles of task `c`,
/// in three loops over the task's particles: their per-particle factors
/// (two divisions each, in lanes), their pair sums, then the accelerations,
/// the kick and the checks (in lanes again). Each particle's operations are
/// those of one loop doing all three, in the same order: the same bits.
#[inline(always)]
pub(super) fn forces_chunk<
    const SYMMETRIC: bool,
    const AV: bool,
    const MIRROR: bool,
    const GATHER: bool,
>(
    c: usize,
    out: ForcesOut,
    input: &ForcesIn,
) -> Forces {
    let (ax, ay, vx, vy) = out;
    let params = input.params;
    let base = c * CHUNK;
    let m = ax.len();
    assert!(m <= CHUNK && ay.len() == m && vx.len() == m && vy.len() == m);
    let (rho, y) = (&input.rho[base..base + m], &input.y[base..base + m]);
    let mut inv_rho = [0.0; CHUNK];
    let mut inv_gap = [0.0; CHUNK];
    // 0 when the walls are not mirrored: beta = 1 + min(D x 0, cap) = 1,
    // exactly, in a loop with the factor ([`forces`]).
    let gap_scale = if params.mirror_walls { 1.0 } else { 0.0 };
    for k in 0..m {
        inv_rho[k] = 1.0 / rho[k];
        // Capped by beta_max anyway: a particle at the plane is no
        // division by zero.
        inv_gap[k] = gap_scale / (params.b - y[k].abs()).max(f64::MIN_POSITIVE);
    }
    let mut sum_x = [0.0; CHUNK];
    let mut sum_y = [0.0; CHUNK];
    for k in 0..m {
        let i = base + k;
        let scales = Scales {
            pressure: if SYMMETRIC {
                params.mass
            } else {
                params.mass * inv_rho[k] * inv_rho[k]
            },
            av: params.av * inv_rho[k],
            visc: params.visc * inv_rho[k],
            inv_gap: inv_gap[k],
            beta_max: params.beta_max,
        };
        let windows = input.list.windows(i);
        let first = input.list.window_start(i) * LANES;
        let args = ForceArgs {
            i,
            windows,
            g: match input.g {
                WindowG::Lanes(lane_g) => {
                    WindowG::Lanes(&lane_g[first..first + windows.len() * LANES])
                }
                WindowG::Gather { pair_g, .. } => WindowG::Gather {
                    sources: input.list.window_sources(i),
                    pair_g,
                },
            },
            xs: (input.x, input.y),
            vs: (input.v_pred_x, input.v_pred_y),
            pressure_term: input.pressure_term,
            vol: input.vol,
            depth: input.depth,
            width: input.width,
            scales,
        };
        (sum_x[k], sum_y[k]) = pair_forces::<AV, MIRROR, GATHER>(args);
    }
    let mut seen = Forces::NONE;
    let (mut a2_max, mut v2_max, mut all) = (0.0f64, 0.0f64, 0.0);
    for k in 0..m {
        let axi = params.grad_scale * sum_x[k] + params.body;
        let ayi = params.grad_scale * sum_y[k];
        ax[k] = axi;
        ay[k] = ayi;
        vx[k] += input.half_dt * axi;
        vy[k] += input.half_dt * ayi;
        let a2 = axi * axi + ayi * ayi;
        let v2 = vx[k] * vx[k] + vy[k] * vy[k];
        // 0 x (a2 + v2) is 0 for every finite sum, NaN otherwise: one
        // test for the task, not a branch per particle.
        all += 0.0 * (a2 + v2);
        a2_max = a2_max.max(a2);
        v2_max = v2_max.max(v2);
    }
    seen.finite = all == 0.0;
    seen.a_max = a2_max.sqrt();
    seen.v_max = v2_max.sqrt();
    seen
}

on_isa! {
    /// [`forces_chunk`] compiled for the instruction set `isa`.
    pub(super) fn forces_chunk_on[
        const SYMMETRIC: bool,
        const AV: bool,
        const MIRROR: bool,
        const GATHER: bool
    ] => forces_chunk[SYMMETRIC, AV, MIRROR, GATHER](
        c: usize,
        out: ForcesOut,
        input: &ForcesIn
    ) -> Forces
}

on_isa! {
    /// [`pair_forces`] alone, for the test that compares instruction sets.
    #[cfg(test)]
    pub(super) fn pair_forces_on[const AV: bool, const MIRROR: bool, const GATHER: bool]
        => pair_forces[AV, MIRROR, GATHER](args: ForceArgs) -> (f64, f64)
}

#[cfg(test)]
mod tests;
