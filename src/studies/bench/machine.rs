//! The machine the bench runs on: its FP64 peak (from the CPU's vector
//! instructions and clock) and its memory bandwidth (measured), the two
//! roofs of the roofline.

use serde::Serialize;

use super::cores;
use crate::solver;

/// The machine and the peak it is measured against.
#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    pub cpu: String,
    pub cores: usize,
    /// Clock from /proc/cpuinfo (`cpu MHz`, the largest over cores); the
    /// nominal clock on a virtual machine, no turbo.
    pub ghz: f64,
    /// The vector instructions of the pair loops (chosen at run time), and
    /// the double-precision flops per cycle and core they allow: lanes x 2
    /// (two FP ports on current x86 cores), no FMA (Rust never fuses a * b +
    /// c, and the solver writes no mul_add). On AMD's Zen 4, which runs a
    /// 512-bit operation on 256-bit pipes, the same 16 for AVX-512: 4 lanes
    /// x 4 pipes (two multiply, two add).
    pub isa_in_use: String,
    pub flops_per_cycle_in_use: f64,
    /// cores x GHz x flops/cycle for the instruction set in use.
    pub peak_gflops_in_use: f64,
    /// The widest vector unit the CPU has (from /proc/cpuinfo flags) with
    /// FMA: lanes x 2 ports x 2 (the usual quoted peak, e.g. AVX2 FMA 16,
    /// AVX-512 FMA 32 DP flops/cycle; 16 on Zen 4, whose AVX-512 runs on
    /// 256-bit pipes).
    pub isa_best: &'static str,
    pub flops_per_cycle_best: f64,
    pub peak_gflops_best: f64,
    /// Memory bandwidth in GB/s, measured ([`stream_gbs`]) on 1 thread and
    /// on every core; 0 when not measured.
    pub stream_gbs_1: f64,
    pub stream_gbs_all: f64,
}

/// Whether the CPU runs 512-bit operations on 256-bit pipes, two passes
/// each: AMD's Zen 4 (family 25 with AVX-512; Zen 5, family 26, has full
/// 512-bit pipes), from /proc/cpuinfo's `vendor_id` and `cpu family`.
fn half_width_avx512(vendor: &str, family: Option<u32>, avx512: bool) -> bool {
    avx512 && vendor == "AuthenticAMD" && family == Some(25)
}

/// (name, flops per cycle and core) of the CPU's widest unit, with FMA.
fn best_isa(avx512: bool, avx: bool, fma: bool, half_width: bool) -> (&'static str, f64) {
    match (avx512, avx, fma) {
        (true, _, _) if half_width => (
            "AVX-512 + FMA on 256-bit pipes (Zen 4: 4 lanes x 2 FMA pipes x 2)",
            16.0,
        ),
        (true, _, _) => ("AVX-512 + FMA (8 lanes x 2 FMA ports x 2)", 32.0),
        (false, true, true) => ("AVX2 + FMA (4 lanes x 2 FMA ports x 2)", 16.0),
        (false, true, false) => ("AVX (4 lanes x add + mul ports)", 8.0),
        _ => ("SSE2 (2 lanes x add + mul ports)", 4.0),
    }
}

impl Machine {
    pub fn detect() -> Machine {
        let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let field = |name: &str| {
            info.lines()
                .filter(|l| l.starts_with(name))
                .filter_map(|l| l.split_once(':').map(|(_, v)| v.trim().to_string()))
                .collect::<Vec<_>>()
        };
        let cpu = field("model name").into_iter().next().unwrap_or_default();
        let mhz = field("cpu MHz")
            .iter()
            .filter_map(|v| v.parse::<f64>().ok())
            .fold(0.0, f64::max);
        let ghz = if mhz > 0.0 { mhz / 1000.0 } else { f64::NAN };
        let flags = field("flags").into_iter().next().unwrap_or_default();
        let has = |f: &str| flags.split_whitespace().any(|x| x == f);
        let vendor = field("vendor_id").into_iter().next().unwrap_or_default();
        let family = field("cpu family").first().and_then(|f| f.parse().ok());
        let half_width = half_width_avx512(&vendor, family, has("avx512f"));
        let (name, lanes) = solver::pair_loop_isa();
        let in_use = 2.0 * f64::from(lanes);
        let isa_in_use = if half_width && lanes == 8 {
            format!("{name} on 256-bit pipes (4 lanes x 2 multiply + 2 add pipes, no FMA)")
        } else {
            format!("{name} ({lanes} lanes x 2 ports, no FMA)")
        };
        let (isa_best, best) = best_isa(has("avx512f"), has("avx"), has("fma"), half_width);
        let cores = cores();
        let peak = |f: f64| cores as f64 * ghz * f;
        Machine {
            cpu,
            cores,
            ghz,
            isa_in_use,
            flops_per_cycle_in_use: in_use,
            peak_gflops_in_use: peak(in_use),
            isa_best,
            flops_per_cycle_best: best,
            peak_gflops_best: peak(best),
            stream_gbs_1: 0.0,
            stream_gbs_all: 0.0,
        }
    }

    /// Measure the memory bandwidth on 1 thread and on every core.
    pub fn measure_bandwidth(&mut self) -> anyhow::Result<()> {
        self.stream_gbs_1 = stream_gbs(1)?;
        self.stream_gbs_all = if self.cores > 1 {
            stream_gbs(self.cores)?
        } else {
            self.stream_gbs_1
        };
        Ok(())
    }

    /// The measured bandwidth for a thread count.
    pub fn bandwidth(&self, threads: usize) -> f64 {
        if threads <= 1 {
            self.stream_gbs_1
        } else {
            self.stream_gbs_all
        }
    }
}

/// f64s per array of the bandwidth loop: 3 arrays of 128 MiB, well past
/// the caches (this machine's last level, as a virtual machine reports it,
/// may be large).
const STREAM_LEN: usize = 1 << 24;

/// A STREAM-like triad a = b + s c over three arrays of [`STREAM_LEN`]
/// f64 on a pool of `threads`, in chunks per task: the best of 4 passes
/// after a first one that touches the pages, in GB/s counting the 24 bytes
/// a pass reads and writes per element (the write-allocate read of a not
/// counted, as STREAM does).
pub fn stream_gbs(threads: usize) -> anyhow::Result<f64> {
    use rayon::prelude::*;
    const CHUNK: usize = 1 << 16;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    Ok(pool.install(|| {
        let mut a = vec![0.0f64; STREAM_LEN];
        let b = vec![1.0f64; STREAM_LEN];
        let c = vec![2.0f64; STREAM_LEN];
        let mut best = f64::INFINITY;
        for pass in 0..5 {
            let s = 0.5 + pass as f64;
            let start = std::time::Instant::now();
            a.par_chunks_mut(CHUNK)
                .zip(b.par_chunks(CHUNK).zip(c.par_chunks(CHUNK)))
                .for_each(|(a, (b, c))| {
                    for ((a, &b), &c) in a.iter_mut().zip(b).zip(c) {
                        *a = b + s * c;
                    }
                });
            let t = start.elapsed().as_secs_f64();
            std::hint::black_box(&a);
            if pass > 0 {
                best = best.min(t);
            }
        }
        (3 * 8 * STREAM_LEN) as f64 / best * 1e-9
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Zen 4 runs AVX-512 on 256-bit pipes: its FMA peak is AVX2's, not
    /// twice it; Intel's AVX-512 cores and Zen 5 have full-width pipes.
    #[test]
    fn zen_4_avx512_peaks_at_the_width_of_its_pipes() {
        let zen4 = half_width_avx512("AuthenticAMD", Some(25), true);
        assert!(zen4);
        assert_eq!(best_isa(true, true, true, zen4).1, 16.0);
        for (vendor, family) in [("GenuineIntel", Some(6)), ("AuthenticAMD", Some(26))] {
            let half = half_width_avx512(vendor, family, true);
            assert!(!half, "{vendor} {family:?}");
            assert_eq!(best_isa(true, true, true, half).1, 32.0);
        }
        assert!(!half_width_avx512("AuthenticAMD", Some(25), false));
        assert_eq!(best_isa(false, true, true, false).1, 16.0);
    }
}
