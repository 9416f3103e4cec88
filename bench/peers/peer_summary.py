"""Summarise alternating runs of PySPH and shearsph (one JSON object per line
and run, as pysph_poiseuille.py and `shearsph bench --pysph-match` print):
each round, the medians, the throughput ratio and both errors; with a third
file (shearsph at other `--layers`), the time shearsph takes to reach PySPH's
accuracy; the last line is the summary as JSON.

usage: peer_summary.py PYSPH.jsonl SHEARSPH.jsonl [LADDER.jsonl]"""
import json
import statistics
import sys


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def main():
    peer, ours = load(sys.argv[1]), load(sys.argv[2])
    print(f"{'round':>5} {'pysph p-steps/s':>16} {'shearsph p-steps/s':>19} {'ratio':>7}")
    for k, (a, b) in enumerate(zip(peer, ours), 1):
        ratio = b["particle_steps_per_s"] / a["particle_steps_per_s"]
        print(f"{k:>5} {a['particle_steps_per_s']:>16.4e} {b['particle_steps_per_s']:>19.4e} {ratio:>7.1f}")
    med = lambda rs: statistics.median(r["particle_steps_per_s"] for r in rs)
    p, s = med(peer), med(ours)
    a, b = peer[-1], ours[-1]
    print()
    for name, r, m in (("pysph", a, p), ("shearsph", b, s)):
        print(f"{name:>8}: {r['particles']} particles, {r['steps']} steps, {r['threads']} threads, "
              f"t nu/B^2 = {r['tau']:.4f}, median {m:.4e} particle-steps/s, "
              f"Linf error {r['linf_rel_err']:.3e} Vmax")
    print(f"throughput ratio shearsph / pysph (medians): {s / p:.1f}")
    summary = {
        "pysph": {**a, "median_particle_steps_per_s": p},
        "shearsph": {**b, "median_particle_steps_per_s": s},
        "ratio": s / p,
        "rounds": len(peer),
    }
    if len(sys.argv) > 3:
        summary["to_accuracy"] = to_accuracy(peer, load(sys.argv[3]))
    print(json.dumps(summary))


def to_accuracy(peer, ladder):
    """The coarsest shearsph run no less accurate than PySPH (its median
    wall time and its error), and the ratio of the wall times."""
    target = statistics.median(r["linf_rel_err"] for r in peer)
    wall = statistics.median(r["wall_s"] for r in peer)
    print()
    print(f"the same flow to the same t nu/B^2 in shearsph, coarser (PySPH: {wall:.3f} s, "
          f"Linf {target:.3e}):")
    print(f"{'layers':>6} {'particles':>9} {'steps':>6} {'wall s':>9} {'Linf/Vmax':>10}")
    for r in ladder:
        print(f"{r['layers']:>6} {r['particles']:>9} {r['steps']:>6} {r['wall_s']:>9.4f} "
              f"{r['linf_rel_err']:>10.3e}")
    ok = [r for r in ladder if r["linf_rel_err"] <= target]
    if not ok:
        print("no shearsph run reached PySPH's accuracy")
        return None
    best = min(ok, key=lambda r: r["wall_s"])
    print(f"fastest no less accurate: {best['layers']} layers, {best['wall_s']:.4f} s: "
          f"{wall / best['wall_s']:.0f}x less wall time than PySPH to its accuracy")
    return {"layers": best["layers"], "wall_s": best["wall_s"],
            "linf_rel_err": best["linf_rel_err"], "pysph_wall_s": wall,
            "pysph_linf_rel_err": target, "wall_time_ratio": wall / best["wall_s"]}


if __name__ == "__main__":
    main()
