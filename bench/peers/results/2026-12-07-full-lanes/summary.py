#!/usr/bin/env python3
"""The A/B's table (ab.sh): per kernel, particle count and form, each
round's ns a particle-step and its force pass's ns per listed pair (the
bench's ns a window lane over the windows' share of listed lanes: every
form evaluates the same list), and the rounds' ratios main / form (above
1: the form is faster)."""
import glob, re, collections

rows = collections.defaultdict(dict)  # (kernel, n, form) -> round -> (nsps, ns_pair)
for f in sorted(glob.glob("round-*-*.txt")):
    r, form = re.match(r"round-(\d)-(\w+)\.txt", f).groups()
    text = open(f).read().splitlines()
    main, passes = {}, {}
    section = None
    for line in text:
        if line.startswith("kernel     particles thr  steps"):
            section = "main"; continue
        if line.startswith("kernel     particles thr  kern%"):
            section = "pass"; continue
        if line.startswith("kernel ") or not line.strip():
            section = None if not line.strip() else section
            continue
        t = line.split()
        if section == "main" and len(t) > 8:
            main[(t[0], t[1])] = float(t[8])
        if section == "pass" and len(t) > 12:
            passes[(t[0], t[1])] = float(t[9]) / (float(t[12]) / 100)
    for k in main:
        rows[(k[0], int(k[1]), form)][r] = (main[k], passes.get(k))

forms = ["main", "gathers", "records", "halves"]
print(f"{'kernel':<12}{'n':>6}  {'form':<8} {'ns/p-step, rounds':<28} {'force ns/pair':<26} main/form")
for kernel, n in sorted({(k, n) for k, n, _ in rows}):
    for form in forms:
        d = rows.get((kernel, n, form), {})
        m = rows.get((kernel, n, "main"), {})
        nsps = ", ".join(f"{d[r][0]:.1f}" for r in sorted(d))
        pair = ", ".join(f"{d[r][1]:.2f}" for r in sorted(d))
        ratios = sorted(m[r][0] / d[r][0] for r in sorted(d) if r in m)
        k = len(ratios)
        med = (ratios[k // 2] + ratios[(k - 1) // 2]) / 2 if k else float("nan")
        ratio = ", ".join(f"{m[r][0] / d[r][0]:.2f}" for r in sorted(d) if r in m)
        print(f"{kernel:<12}{n:>6}  {form:<8} {nsps:<28} {pair:<26} {ratio}  (median {med:.2f})")
