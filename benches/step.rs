//! One full solver step (kick and drift, neighbour list when stale, density,
//! forces) per kernel, at a mid-size scene of about 10^4 particles: the
//! bench scene of `shearsph bench` (steady profile, Re = 10, c0 = 10 U), on
//! rayon's default pool (all cores).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use shearsph::bench::{layers_for, scene};
use shearsph::kernel::{Kernel, KernelVisitor};
use shearsph::kernels::{with_kernel, NAMES};
use shearsph::problem::Problem;
use shearsph::solver::Stepper;

const PARTICLES: usize = 10_000;

struct Bench<'a>(&'a mut Criterion);

impl KernelVisitor for Bench<'_> {
    type Output = ();
    fn visit<K: Kernel>(self) {
        let mut s = scene(K::NAME);
        s.n_layers = layers_for(&s, PARTICLES).expect("a valid bench scene");
        let problem = Problem::resolve(&s, K::INFO).expect("a valid bench scene");
        let mut stepper = Stepper::<K>::new(&problem);
        let mut g = self.0.benchmark_group(format!("step/{}", K::NAME));
        g.throughput(Throughput::Elements(stepper.particles() as u64));
        g.bench_function(format!("{}_particles", stepper.particles()), |b| {
            b.iter(|| {
                assert!(stepper.step().is_none(), "the bench scene runs cleanly");
            })
        });
        g.finish();
    }
}

fn steps(c: &mut Criterion) {
    for name in NAMES {
        with_kernel(name, Bench(c));
    }
}

criterion_group!(benches, steps);
criterion_main!(benches);
