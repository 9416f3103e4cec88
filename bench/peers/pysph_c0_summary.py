"""The agreement table of bench/peers/pysph_c0_all.sh, from the runs in OUT:
per scene, shearsph's answer (its compaction bound, from
c0-empirical-reRE.txt, the output of `shearsph c0 --empirical`), PySPH's
c0_min per scheme (bisect-SCHEME-reRE.json, pysph_c0_bisect.py), the ratio
and whether they agree within a factor 1.5; the disordered law's k and m in
each code and scheme (pysph_c0_table.py's fit over every jittered c0 run in
OUT); the time to disorder of a small jitter in each
(disorder-*-reRE-c*-jJ-s1.json, pysph_c0_disorder.sh); and, where a run
switched one of TVF's differences off (schemes tvf_pb0, tvf_cubic,
tvf_walls), its pooled eps_stat and linf_stat beside TVF's at the same c0.

usage: python3 pysph_c0_summary.py OUT
"""
import glob
import json
import os
import re
import sys

import pysph_c0_table as table

SCHEMES = ["matched", "tvf"]
VARIANTS = {"tvf_pb0": "TVF without its background pressure (pb = 0)",
            "tvf_cubic": "TVF with the cubic spline (support 2h) instead of the quintic",
            "tvf_walls": "TVF on the matched scheme's 380 particles and walls (|n| = N..N+4)"}


def shearsph_answer(out, re_):
    """(compaction bound, over-compressed below, mean-flow error there, ok?)
    from `c0 --empirical`'s text output."""
    path = os.path.join(out, "c0-empirical-re%g.txt" % re_)
    if not os.path.exists(path):
        return None
    text = open(path).read()
    m = re.search(r"the compaction needs c0 >= ([0-9.]+) U, where the mean flow is off by ([0-9.e-]+) U",
                  text)
    ok = "no c0 from" not in text
    lw = re.search(r"disordered law: [^\n]*k = ([0-9.e-]+) [^\n]*m = ([0-9.e-]+) [^\n]*?(\d+ trials, c0 = [^)]*)\)",
                   text)
    return dict(c0=float(m.group(1)), linf=float(m.group(2)), ok=ok,
                law=lw.groups() if lw else None) if m else None


def main():
    out = sys.argv[1]
    runs = table.load(out)
    res = sorted({r["re"] for r in runs})
    for re_ in res:
        print("== Re = %g, N = 10, square lattice h = d, jitter 0.05 d, 3 seeds pooled ==" % re_)
        sh = shearsph_answer(out, re_)
        if sh:
            print("shearsph (c0 --empirical): eps_stat <= eps0 + 0.01 from %g U, mean flow off by %g U "
                  "there: %s" % (sh["c0"], sh["linf"], "ok" if sh["ok"] else "no c0 ok"))
        for scheme in SCHEMES:
            path = os.path.join(out, "bisect-%s-re%g.json" % (scheme, re_))
            if not os.path.exists(path):
                print("pysph-%-8s c0_min: not bisected" % scheme)
                continue
            b = json.load(open(path))
            c = b["c0_compaction"]
            line = "pysph-%-8s eps_stat <= eps0 + 0.01 from %g U (over-compressed at %s U), %d seeds pooled, " \
                   "bracket to %g %%; there linf %.3g U: %s" % (
                       scheme, c, "%g" % b["compressed_below"] if b["compressed_below"] else "-",
                       b["seeds"], 100 * b["rel_tol"], b["linf_there"],
                       "ok" if b["c0_min_ok"] else "no c0 ok at the bound")
            print(line)
            if sh and c:
                ratio = c / sh["c0"]
                print("    PySPH-%s / shearsph = %.3f: %s within a factor 1.5" % (
                    scheme, ratio, "agree" if 1 / 1.5 <= ratio <= 1.5 else "do NOT agree"))
        if sh and sh.get("law"):
            print("law shearsph       eps_stat - eps0 = %s (U/c0)^%s over c0 --empirical's own trials (%s)"
                  % sh["law"])
        # each code's law over its own jittered c0s; shearsph's and the
        # matched scheme's also over the c0s both ran (the same rungs)
        both = {r["c0"] for r in runs if r["re"] == re_ and r["code"] == "pysph-matched" and r["seed"] > 0}
        every = {r["c0"] for r in runs if r["re"] == re_ and r["code"] == "shearsph" and r["seed"] > 0}
        for code, only, what in (("shearsph", both, "the matched scheme's c0s"),
                                 ("pysph-matched", both, "its c0s"),
                                 ("shearsph", None, "every c0 it ran here"),
                                 ("pysph-tvf", None, "its c0s")):
            if code == "shearsph" and only is None and every == both:
                continue
            f = table.law(runs, code, re_, only)
            if f:
                k, m, cs = f
                print("law %-14s eps_stat - eps0 = %.3g (U/c0)^%.3g over %s (c0/U = %s); c0 for 0.01: %.3g U" % (
                    code, k, m, what, ",".join("%.4g" % c for c in cs), (k / 0.01) ** (1 / m)))
            else:
                print("law %-14s not fitted over %s: fewer than two jittered c0s disordered with an excess "
                      ">= max(1e-3, eps0)" % (code, what))
        for path in sorted(glob.glob(os.path.join(out, "disorder-shearsph-re%g-c*-s1.json" % re_))):
            tag = re.search(r"disorder-shearsph-(.*)\.json$", path).group(1)
            s = json.load(open(path))
            parts = ["shearsph %s" % ("%.1f" % s["t_disorder"] if s["t_disorder"] is not None
                                      else "none by t = %g" % s["t"])]
            for scheme in SCHEMES:
                pp = os.path.join(out, "disorder-pysph-%s-%s.json" % (scheme, tag))
                if os.path.exists(pp) and os.path.getsize(pp) > 0:
                    p = json.load(open(pp))
                    parts.append("pysph-%s %s" % (scheme, "%.1f" % p["t_disorder"] if p["t_disorder"]
                                                  is not None else "none by t = %g (dy_rms %.3g d)"
                                                  % (p["t"], p["dy_rms"])))
            j = re.search(r"-j([0-9.]+)-", tag).group(1)
            print("time to disorder, jitter %s d (seed 1), c0 %g U: %s" % (j, s["c0_over_u"], ", ".join(parts)))
        for v, what in VARIANTS.items():
            for c0 in sorted({r["c0"] for r in runs if r["re"] == re_ and r["code"] == "pysph-" + v}):
                for perfect in (False, True):
                    pv = table.pooled(runs, "pysph-" + v, re_, c0, perfect)
                    if not pv:
                        continue
                    same = [r["seed"] for r in pv["runs"]]  # the others on the same starts
                    pt = table.pooled(runs, "pysph-tvf", re_, c0, perfect, same)
                    pm = table.pooled(runs, "pysph-matched", re_, c0, perfect, same)
                    ps = table.pooled(runs, "shearsph", re_, c0, perfect, same)
                    seeds = ",".join(str(r["seed"]) for r in pv["runs"])
                    def el(p):
                        return ("eps_stat %.4g, linf %.3g, t_disorder %s" % (
                            p["eps"], p["linf"], "/".join("%.0f" % r["t_disorder"] if r["t_disorder"]
                                                          is not None else "-" for r in p["runs"]))
                                if p else "-")
                    print("switch: %s, c0 %g U, %s:\n    switched %s (%s)\n    TVF %s\n    matched %s\n"
                          "    shearsph %s" % (
                              what, c0, "perfect lattice" if perfect else "seed " + seeds,
                              el(pv), pv["cls"], el(pt), el(pm), el(ps)))
                    if pt and ps:
                        print("    eps_stat / shearsph's on the same start: TVF %.3g, switched %.3g; class: TVF %s, "
                              "switched %s, shearsph %s" % (
                                  pt["eps"] / ps["eps"], pv["eps"] / ps["eps"], pt["cls"], pv["cls"],
                                  ps["cls"]))
        print()


if __name__ == "__main__":
    main()
