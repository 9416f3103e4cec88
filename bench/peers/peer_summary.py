"""Summarise alternating runs of PySPH and shearsph (one JSON object per line
and run, as pysph_poiseuille.py and `shearsph bench --pysph-match` print):
each round, the medians, the throughput ratio and both errors; the last line
is the summary as JSON."""
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
    print(json.dumps({
        "pysph": {**a, "median_particle_steps_per_s": p},
        "shearsph": {**b, "median_particle_steps_per_s": s},
        "ratio": s / p,
        "rounds": len(peer),
    }))


if __name__ == "__main__":
    main()
