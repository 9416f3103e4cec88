//! One neighbour-list rebuild: the SPHinXsys-matched scene (2760 particles,
//! Wendland C2 on the square lattice at h = 1.3 d, the scene whose list
//! rebuilds about every 28 steps at the CFL factor 0.5) and the `shearsph bench` scene of the same
//! kernel at about 10^4 and 10^5 particles, each with its layers sheared
//! past each other (a parabolic shift of up to 7.3 d in x, wrapped: the
//! lattice as the flow leaves it between rebuilds), on rayon's default pool;
//! and a disordered fluid: the Monaghan kernel's lattice at N = 10 on a
//! strip three channels wide (the `bench --disordered` scene's first size),
//! each particle moved by up to 0.45 d in x and y (its lattice row order
//! kept, as the solver keeps a disordered fluid's bands of y), on one
//! thread, as a disordered fluid's build (its form chosen by its cost,
//! `NeighbourList::set_disordered`): there the distance tests go either way.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use shearsph::bench::{layers_for, scene, sphinxsys_match_problem, PEER_MATCH_CFL};
use shearsph::config::ViscousNormalisation;
use shearsph::kernel::Kernel;
use shearsph::kernels::{Monaghan, WendlandC2};
use shearsph::problem::Problem;
use shearsph::solver::neighbours::NeighbourList;

fn rebuild(c: &mut Criterion, label: &str, problem: &Problem) {
    let lat = problem.lattice;
    let (mut x, y, _) = lat.positions();
    let b = lat.b();
    for (x, &y) in x.iter_mut().zip(&y) {
        let shift = 7.3 * lat.d * (1.0 - (y / b).powi(2)).max(0.0);
        *x = (*x + shift).rem_euclid(lat.width);
    }
    let cutoff = (WendlandC2::SUPPORT2_CLOSED.sqrt() + problem.skin) * lat.h;
    let block = lat.columns as usize;
    let mut list = NeighbourList::default();
    let mut g = c.benchmark_group("rebuild");
    g.throughput(Throughput::Elements(x.len() as u64));
    g.bench_function(format!("{label}_{}_particles", x.len()), |bench| {
        bench.iter(|| list.build(&x, &y, lat.width, cutoff, block))
    });
    g.finish();
}

fn rebuilds(c: &mut Criterion) {
    let matched = sphinxsys_match_problem(
        10,
        1.0,
        Some(120),
        ViscousNormalisation::Lattice,
        Some(PEER_MATCH_CFL),
    )
    .expect("the matched scene");
    rebuild(c, "sphinxsys_match", &matched);
    for particles in [10_000, 100_000] {
        let mut s = scene(WendlandC2::NAME);
        s.n_layers = layers_for(&s, particles).expect("a valid bench scene");
        let problem = Problem::resolve(&s, WendlandC2::INFO).expect("a valid bench scene");
        rebuild(c, "bench_wendland_c2", &problem);
    }
}

/// The disordered fluid's rebuild (see the top).
fn disordered(c: &mut Criterion) {
    let mut s = scene(Monaghan::NAME);
    s.n_layers = 10;
    s.columns = Some(54);
    let problem = Problem::resolve(&s, Monaghan::INFO).expect("a valid scene");
    let lat = problem.lattice;
    let (mut x, mut y, _) = lat.positions();
    // A fixed sequence in [-1, 1) (an LCG's top bits): the same fluid each run.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    for (x, y) in x.iter_mut().zip(y.iter_mut()) {
        *x = (*x + 0.45 * lat.d * uniform()).rem_euclid(lat.width);
        *y += 0.45 * lat.d * uniform();
    }
    let cutoff = (Monaghan::SUPPORT2_CLOSED.sqrt() + problem.skin) * lat.h;
    let block = lat.columns as usize;
    let mut list = NeighbourList::default();
    list.set_disordered(true);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let mut g = c.benchmark_group("rebuild");
    g.throughput(Throughput::Elements(x.len() as u64));
    g.bench_function(
        format!("disordered_monaghan_{}_particles", x.len()),
        |bench| bench.iter(|| pool.install(|| list.build(&x, &y, lat.width, cutoff, block))),
    );
    g.finish();
}

criterion_group!(benches, rebuilds, disordered);
criterion_main!(benches);
