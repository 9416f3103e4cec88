"""Summarise a peer comparison from bench/peers/: alternating matched rounds
of a peer (PySPH or SPHinXsys) and shearsph, and both codes laddered over
resolution to the same physical time t nu / B^2. One JSON object per line
and run, as pysph_poiseuille.py, the SPHinXsys case (through peer_metric.py)
and `shearsph bench --pysph-match` / `--sphinxsys-match` print them.

Prints each round, the median throughputs, their ratio and both errors; each
code's ladder per thread count (error against wall time); and for each target
accuracy the wall time each code needs to reach it, two ways:
- "first rung": the cheapest rung of the ladder at or below the target,
  within a relative tolerance REL_TOL = 1e-6 (an error printed to 4 digits
  that equals the target is at it; an upper bound on what the code needs,
  at the resolutions tried);
- "interpolated": on the ladder's Pareto front (rungs sorted by wall time,
  each kept only if more accurate than every cheaper one), log-log linear
  between the last rung above the target and the first at or below it.
The default targets: the peer's error at its matched resolution (the
accuracy its own example delivers; the median over rounds), and the tightest
accuracy that every code and thread count reaches on its ladder (the largest
of their best errors). The last line is the summary as JSON.

usage: peer_summary.py [--peer P.jsonl] [--ours S.jsonl] [--ladder L.jsonl]
                       [--targets E1,E2] [--csv OUT.csv] [--load TEXT]
"""
import argparse
import csv
import json
import math
import os
import statistics
import sys


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def side(run):
    """Which code a run is from, by its `code` field."""
    code = run["code"].lower()
    for name in ("pysph", "sphinxsys", "shearsph"):
        if code.startswith(name):
            return name
    raise ValueError(f"unknown code {run['code']!r}")


def half_width(run):
    """Resolution as particles across the half-width B: shearsph's layers,
    PySPH's rows / 2, SPHinXsys's layers."""
    if "layers" in run:
        return run["layers"]
    return run["rows"] / 2


def pareto(rungs):
    """Rungs sorted by wall time, each more accurate than every cheaper one."""
    front, best = [], math.inf
    for r in sorted(rungs, key=lambda r: r["wall_s"]):
        if r["linf_rel_err"] < best:
            front.append(r)
            best = r["linf_rel_err"]
    return front


REL_TOL = 1e-6


def reaches(err, target):
    """err at or below target, within the relative tolerance REL_TOL."""
    return err <= target * (1.0 + REL_TOL)


def time_to(rungs, target):
    """(first rung at or below target or None, interpolated wall time or None)."""
    ok = [r for r in rungs if reaches(r["linf_rel_err"], target)]
    first = min(ok, key=lambda r: r["wall_s"]) if ok else None
    front = pareto(rungs)
    interp = None
    for a, b in zip(front, front[1:]):
        if not reaches(a["linf_rel_err"], target) and reaches(b["linf_rel_err"], target):
            la, lb = math.log(a["linf_rel_err"]), math.log(b["linf_rel_err"])
            w = (math.log(target) - la) / (lb - la)
            interp = math.exp(math.log(a["wall_s"]) + w * (math.log(b["wall_s"]) - math.log(a["wall_s"])))
            break
    if interp is None and front and reaches(front[0]["linf_rel_err"], target):
        interp = front[0]["wall_s"]  # the cheapest rung already reaches it: no lower bound known
    return first, interp


def rounds(peer, ours):
    """The matched rounds, per thread count: each round, the medians, the
    ratio. `ours` may be empty (the peer alone)."""
    name = side(peer[0])
    med = lambda rs, key: statistics.median(r[key] for r in rs)
    out = {"rounds": {}}
    for thr in sorted({r["threads"] for r in peer}):
        ps = [r for r in peer if r["threads"] == thr]
        os_ = [r for r in ours if r["threads"] == thr]
        print(f"matched scene, {thr} thread(s):")
        print(f"{'round':>5} {name + ' p-steps/s':>20} {'shearsph p-steps/s':>19} {'ratio':>7}")
        for k, a in enumerate(ps):
            b = os_[k] if k < len(os_) else None
            btext = f"{b['particle_steps_per_s']:>19.4e} {b['particle_steps_per_s'] / a['particle_steps_per_s']:>7.1f}" \
                if b else f"{'-':>19} {'-':>7}"
            print(f"{k + 1:>5} {a['particle_steps_per_s']:>20.4e} {btext}")
        entry = {}
        for label, rs in ((name, ps), ("shearsph", os_)):
            if not rs:
                continue
            r = rs[-1]
            m = med(rs, "particle_steps_per_s")
            print(f"{label:>9}: {r['particles']} particles, {r['steps']} steps, "
                  f"t nu/B^2 = {r['tau']:.4f}, median {m:.4e} particle-steps/s, "
                  f"median wall {med(rs, 'wall_s'):.4g} s, Linf error {med(rs, 'linf_rel_err'):.3e} U")
            entry[label] = {**r, "median_particle_steps_per_s": m, "median_wall_s": med(rs, "wall_s"),
                            "median_linf_rel_err": med(rs, "linf_rel_err"), "rounds": len(rs)}
        if os_:
            ratio = entry["shearsph"]["median_particle_steps_per_s"] / entry[name]["median_particle_steps_per_s"]
            print(f"throughput ratio shearsph / {name} (medians): {ratio:.1f}")
            print(f"wall-time ratio {name} / shearsph (medians, each on its own matched scene): "
                  f"{entry[name]['median_wall_s'] / entry['shearsph']['median_wall_s']:.1f}")
            entry["ratio"] = ratio
        print()
        out["rounds"][str(thr)] = entry
    return out


def ladders(runs, targets):
    groups = {}
    for r in runs:
        groups.setdefault((side(r), r["threads"]), []).append(r)
    print("ladders: the same flow to the same t nu/B^2 at other resolutions (one run per rung)")
    print(f"{'code':>9} {'thr':>3} {'B/dx':>5} {'particles':>9} {'steps':>7} {'t nu/B^2':>9} "
          f"{'wall s':>10} {'Linf/U':>10}")
    for (name, thr), rs in sorted(groups.items()):
        for r in sorted(rs, key=lambda r: r["wall_s"]):
            print(f"{name:>9} {thr:>3} {half_width(r):>5g} {r['particles']:>9} {r['steps']:>7} "
                  f"{r['tau']:>9.4f} {r['wall_s']:>10.4g} {r['linf_rel_err']:>10.3e}")
    out = []
    for target in targets:
        print()
        print(f"wall time to Linf <= {target:.3e} U (first rung at or below it; interpolated "
              "log-log on the ladder's Pareto front):")
        row = {"target": target, "codes": []}
        for (name, thr), rs in sorted(groups.items()):
            first, interp = time_to(rs, target)
            if first is None:
                print(f"{name:>9} {thr} thread(s): not reached (best {min(r['linf_rel_err'] for r in rs):.3e})")
                row["codes"].append({"code": name, "threads": thr, "reached": False})
                continue
            itext = f"{interp:.4g} s" if interp is not None else "n/a"
            print(f"{name:>9} {thr} thread(s): first rung B/dx = {half_width(first):g}, "
                  f"{first['wall_s']:.4g} s (Linf {first['linf_rel_err']:.3e}); interpolated {itext}")
            row["codes"].append({"code": name, "threads": thr, "reached": True,
                                 "first_half_width": half_width(first), "first_wall_s": first["wall_s"],
                                 "first_linf_rel_err": first["linf_rel_err"], "interpolated_wall_s": interp})
        by = {(c["code"], c["threads"]): c for c in row["codes"] if c["reached"]}
        for thr in sorted({t for _, t in groups}):
            peers = [n for n, t in by if t == thr and n != "shearsph"]
            if ("shearsph", thr) not in by:
                continue
            ours = by[("shearsph", thr)]
            for n in peers:
                p = by[(n, thr)]
                ratio_first = p["first_wall_s"] / ours["first_wall_s"]
                text = f"  {thr} thread(s): {n} / shearsph wall time to it: first rung {ratio_first:.0f}x"
                if p["interpolated_wall_s"] and ours["interpolated_wall_s"]:
                    text += f", interpolated {p['interpolated_wall_s'] / ours['interpolated_wall_s']:.0f}x"
                print(text)
        out.append(row)
    return out


def write_csv(path, runs):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["code", "threads", "half_width", "particles", "steps", "tau", "wall_s", "linf_rel_err"])
        for r in runs:
            w.writerow([side(r), r["threads"], half_width(r), r["particles"], r["steps"], r["tau"],
                        r["wall_s"], r["linf_rel_err"]])
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--peer", help="the peer's matched rounds (none: the ladders alone)")
    ap.add_argument("--ours", help="shearsph's matched rounds (none: the peer alone)")
    ap.add_argument("--ladder")
    ap.add_argument("--targets", help="comma-separated Linf/U targets")
    ap.add_argument("--csv", help="write the ladders here (code, threads, half_width, ...)")
    ap.add_argument("--load", help="a note on the machine's load, printed first")
    a = ap.parse_args()
    if a.load:
        print(a.load)
        print()
    peer, ours = (load(a.peer) if a.peer else []), (load(a.ours) if a.ours else [])
    summary = rounds(peer, ours) if peer else {}
    if a.ladder:
        runs = load(a.ladder)
        if a.targets:
            targets = [float(t) for t in a.targets.split(",")]
        else:
            groups = {}
            for r in runs:
                groups.setdefault((side(r), r["threads"]), []).append(r["linf_rel_err"])
            common = max(min(v) for v in groups.values())
            targets = {common}
            if peer:
                targets.add(statistics.median(r["linf_rel_err"] for r in peer))
            targets = sorted(targets, reverse=True)
        summary["to_accuracy"] = ladders(runs, targets)
        if a.csv:
            write_csv(a.csv, runs)
            print(f"\nladders written to {a.csv}")
    if a.load:
        summary["load"] = a.load
    print(json.dumps(summary))


if __name__ == "__main__":
    sys.exit(main())
