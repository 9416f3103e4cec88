//! The generated kernel functions in the solver's hot loop: one evaluation of
//! W and (dW/dq)/q over a spread of q^2 inside the support, per kernel.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use shearsph::kernel::{Kernel, KernelVisitor};
use shearsph::kernels::{with_kernel, NAMES};

struct Bench<'a>(&'a mut Criterion);

impl KernelVisitor for Bench<'_> {
    type Output = ();
    fn visit<K: Kernel>(self) {
        // 1024 q^2 values spread over (0, R^2], as neighbours are
        let q2: Vec<f64> = (1..=1024)
            .map(|i| K::SUPPORT * K::SUPPORT * i as f64 / 1024.0)
            .collect();
        let mut g = self.0.benchmark_group(format!("kernel/{}", K::NAME));
        g.throughput(Throughput::Elements(q2.len() as u64));
        g.bench_function("w", |b| {
            b.iter(|| black_box(&q2).iter().map(|&q| K::w(q)).sum::<f64>())
        });
        g.bench_function("dw_over_q", |b| {
            b.iter(|| black_box(&q2).iter().map(|&q| K::dw_over_q(q)).sum::<f64>())
        });
        g.bench_function("w+dw_over_q", |b| {
            b.iter(|| {
                black_box(&q2)
                    .iter()
                    .map(|&q| K::w(q) + K::dw_over_q(q))
                    .sum::<f64>()
            })
        });
        g.finish();
    }
}

fn kernels(c: &mut Criterion) {
    for name in NAMES {
        with_kernel(name, Bench(c));
    }
}

criterion_group!(benches, kernels);
criterion_main!(benches);
