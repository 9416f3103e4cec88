//! `shearsph bench`'s report as a text table.

use super::Report;

/// The report as a text table.
pub fn table(r: &Report) -> String {
    let m = &r.machine;
    let mut out = String::new();
    out.push_str(&format!(
        "machine: {} | {} cores at {:.2} GHz (/proc/cpuinfo)\n",
        m.cpu, m.cores, m.ghz
    ));
    out.push_str(&format!(
        "peak = cores x GHz x DP flops/cycle/core. In use (pair loops): {}: {} -> {:.1} GFLOP/s; \
         the CPU's best, {}: {} -> {:.1} GFLOP/s\n",
        m.isa_in_use,
        m.flops_per_cycle_in_use,
        m.peak_gflops_in_use,
        m.isa_best,
        m.flops_per_cycle_best,
        m.peak_gflops_best
    ));
    out.push_str(&format!(
        "memory bandwidth (triad over 3 x 128 MiB, measured): {:.1} GB/s on 1 thread, {:.1} GB/s on {} \
         cores\n",
        m.stream_gbs_1, m.stream_gbs_all, m.cores
    ));
    out.push_str(&format!("scene: {}\n\n", r.scene));
    if !r.bases.is_empty() {
        out.push_str(
            "the disordered base each size tiles (dy_rms >= 0.1 d: disordered; eps_p99 its compaction):\n",
        );
        out.push_str(&format!(
            "{:<10} {:>9} {:>7} {:>8} {:>7} {:>7} {:>9}  failure\n",
            "kernel", "particles", "columns", "t", "steps", "dy_rms", "eps_p99"
        ));
        for b in &r.bases {
            out.push_str(&format!(
                "{:<10} {:>9} {:>7} {:>8.1} {:>7} {:>7.3} {:>9.3e}  {}\n",
                b.kernel,
                b.particles,
                b.columns,
                b.t,
                b.steps,
                b.dy_rms,
                b.eps_p99,
                b.failure.as_deref().unwrap_or("-")
            ));
        }
        out.push('\n');
    }
    out.push_str(&format!(
        "{:<10} {:>8} {:>3} {:>6} {:>9} {:>12} {:>12} {:>7} {:>8} {:>6} {:>6} {:>7} {:>6} {:>8} {:>4}\n",
        "kernel",
        "particles",
        "thr",
        "steps",
        "s/step",
        "p-steps/s",
        "pairs/s",
        "ns/pair",
        "ns/p-step",
        "GF/s",
        "%peak",
        "%best",
        "B/part",
        "HWM MiB",
        "ok"
    ));
    for row in &r.rows {
        out.push_str(&format!(
            "{:<10} {:>8} {:>3} {:>6} {:>9.3e} {:>12.4e} {:>12.4e} {:>7.2} {:>8.1} {:>6.2} {:>6.1} {:>7.2} {:>6.0} {:>8.1} {:>4}\n",
            row.kernel,
            row.particles,
            row.threads,
            row.steps,
            row.wall_s / row.steps.max(1) as f64,
            row.particle_steps_per_s,
            row.pairs_per_s,
            row.ns_per_pair,
            row.ns_per_particle_step,
            row.gflops,
            100.0 * row.fraction_of_peak_in_use,
            100.0 * row.fraction_of_peak_best,
            row.bytes_per_particle,
            row.vm_hwm_bytes.map_or(f64::NAN, |b| b as f64 / (1 << 20) as f64),
            if row.ok { "ok" } else { "FAIL" },
        ));
    }
    out.push_str(
        "\nroofline of the pair passes (density and forces, timed inside the solver): their share \
         of the step,\ntheir GFLOP/s and fraction of the peaks, the bytes they move per pair at the \
         least (every array once\nper pass), flops per byte, and the roof min(peak in use, flops/byte \
         x bandwidth) for the threads used:\n",
    );
    out.push_str(&format!(
        "{:<10} {:>8} {:>3} {:>6} {:>7} {:>6} {:>6} {:>7} {:>6} {:>8} {:>6}\n",
        "kernel",
        "particles",
        "thr",
        "loops%",
        "GF/s",
        "%peak",
        "%best",
        "B/pair",
        "F/B",
        "roof GF/s",
        "%roof"
    ));
    for row in &r.rows {
        out.push_str(&format!(
            "{:<10} {:>8} {:>3} {:>6.1} {:>7.2} {:>6.1} {:>6.2} {:>7.1} {:>6.2} {:>8.2} {:>6.1}\n",
            row.kernel,
            row.particles,
            row.threads,
            100.0 * row.pair_loop_share,
            row.pair_loop_gflops,
            100.0 * row.pair_loop_fraction_of_peak_in_use,
            100.0 * row.pair_loop_fraction_of_peak_best,
            row.bytes_per_pair,
            row.flops_per_byte,
            row.roofline_gflops,
            100.0 * row.pair_loop_gflops / row.roofline_gflops,
        ));
    }
    out.push_str(
        "\npass by pass (timed inside the solver, the last repeat): each pass's share of the step; \
         the kernel\npass's core-ns per pair evaluated against the kernel alone in lanes with its \
         values in the first-level\ncache (ratio near 1: bound by the kernel's own square root and \
         division, not by memory); the force\npass's core-ns per lane run against the bound its flops \
         set at the peak in use, and its lanes' share\nthat are listed pairs; the share of the \
         step spent rebuilding the neighbour list (list%, with its rebuilds); where the force \
         pass\nread (dW/dq)/q (g: a window-lane table, or gathered from the pairs' table); the \
         f64 lanes of the vectors the\nkernel pass, the sums and the force pass ran with, as \
         their cost picked (vec):\n",
    );
    out.push_str(&format!(
        "{:<10} {:>8} {:>3} {:>6} {:>6} {:>6} {:>7} {:>7} {:>5} {:>7} {:>7} {:>5} {:>6} {:>6} {:>5} {:>5} {:>5}\n",
        "kernel",
        "particles",
        "thr",
        "kern%",
        "sums%",
        "forc%",
        "kern ns",
        "alone",
        "x",
        "ns/lane",
        "bound",
        "x",
        "lanes%",
        "list%",
        "rebu",
        "g",
        "vec"
    ));
    for row in &r.rows {
        let [kern, sums, forc] = row.pass_share;
        out.push_str(&format!(
            "{:<10} {:>8} {:>3} {:>6.1} {:>6.1} {:>6.1} {:>7.2} {:>7.2} {:>5.2} {:>7.3} {:>7.3} {:>5.2} {:>6.1} {:>6.1} {:>5} {:>5} {:>5}\n",
            row.kernel,
            row.particles,
            row.threads,
            100.0 * kern,
            100.0 * sums,
            100.0 * forc,
            row.kernel_pass_ns,
            row.kernel_alone_ns,
            row.kernel_pass_ns / row.kernel_alone_ns,
            row.forces_ns_per_lane,
            row.forces_lane_bound_ns,
            row.forces_ns_per_lane / row.forces_lane_bound_ns,
            100.0 * row.lane_use,
            100.0 * row.rebuild_share,
            row.neighbour_rebuilds,
            row.force_g,
            row.pass_lanes.map(|l| l.to_string()).join("/"),
        ));
    }
    out.push_str(
        "\nthe floor the work's form sets (each own pair's kernel at the kernel-alone rate, each \
         force-pass lane at\nits flop bound, per particle; memory, gathers, the density sums and \
         the kick left out) against the\nstep's core-ns per particle, and the kernel's share of \
         the floor:\n",
    );
    out.push_str(&format!(
        "{:<10} {:>8} {:>3} {:>10} {:>8} {:>5} {:>7}\n",
        "kernel", "particles", "thr", "core-ns/ps", "floor", "x", "kern%"
    ));
    for row in &r.rows {
        out.push_str(&format!(
            "{:<10} {:>8} {:>3} {:>10.1} {:>8.1} {:>5.2} {:>7.1}\n",
            row.kernel,
            row.particles,
            row.threads,
            row.core_ns_per_particle_step,
            row.floor_core_ns_per_particle_step,
            row.core_ns_per_particle_step / row.floor_core_ns_per_particle_step,
            100.0 * row.floor_kernel_share,
        ));
    }
    if !r.scaling.is_empty() {
        out.push_str("\ncost per step ~ particles^k (least squares over the counts above):\n");
        for s in &r.scaling {
            out.push_str(&format!(
                "  {:<10} {} thread(s): k = {:.3}; ns per particle-step {:.1} -> {:.1}\n",
                s.kernel,
                s.threads,
                s.exponent,
                s.ns_per_particle_step_first,
                s.ns_per_particle_step_last
            ));
        }
    }
    out
}
