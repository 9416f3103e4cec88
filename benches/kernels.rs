//! The generated kernel code as the program calls it, per kernel: W alone
//! (the density's self term), (W, (dW/dq)/q) without branches over a spread
//! of q^2 inside the support (the solver's pair loops), and eps(t, n) on the
//! paper's discretisation and the last one generated (the report's Figure 4
//! curves).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use shearsph::kernel::{Kernel, KernelVisitor};
use shearsph::kernels::{with_kernel, NAMES};

struct Bench<'a>(&'a mut Criterion);

impl KernelVisitor for Bench<'_> {
    type Output = ();
    fn visit<K: Kernel>(self) {
        // 1024 q^2 values spread over (0, R^2], as neighbours are
        let r2 = K::INFO.support * K::INFO.support;
        let q2: Vec<f64> = (1..=1024).map(|i| r2 * i as f64 / 1024.0).collect();
        let mut g = self.0.benchmark_group(format!("kernel/{}", K::NAME));
        g.throughput(Throughput::Elements(q2.len() as u64));
        g.bench_function("w", |b| {
            b.iter(|| black_box(&q2).iter().map(|&q| K::w(q)).sum::<f64>())
        });
        g.bench_function("w_dw_over_q_lanes", |b| {
            b.iter(|| {
                black_box(&q2)
                    .iter()
                    .map(|&q| {
                        let (w, g) = K::w_dw_over_q_lanes(q);
                        w + g
                    })
                    .sum::<f64>()
            })
        });
        g.finish();
        // eps(t, n) at 64 times of the period, for a particle of layer 3 near
        // walls at N = 8
        let ts: Vec<f64> = (0..64).map(|i| i as f64 / 64.0).collect();
        let mut g = self.0.benchmark_group(format!("eps_at/{}", K::NAME));
        g.throughput(Throughput::Elements(ts.len() as u64));
        let discs = K::INFO.discretisations;
        for (label, d) in [("paper", &discs[0]), ("last", &discs[discs.len() - 1])] {
            g.bench_function(label, |b| {
                b.iter(|| {
                    black_box(&ts)
                        .iter()
                        .map(|&t| (d.eps_at)(t, 3, Some(8)))
                        .sum::<f64>()
                })
            });
        }
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
