"""Each run's core use (CPU s / wall s) and the old / new wall ratios of
ab.sh's folders, pooled: coreuse.py FOLDER..  (each FOLDER holds
{old,new}-reRE-I.time)."""
import glob
import statistics
import sys

for re in ("1", "10"):
    use = {"old": [], "new": []}
    ratios = []
    for folder in sys.argv[1:]:
        times = {}
        for t in glob.glob(f"{folder}/*-re{re}-*.time"):
            side, i = t.rsplit("/", 1)[1].split("-re")[0], t.rsplit("-", 1)[1].split(".")[0]
            wall, user, sys_ = (float(x) for x in open(t).read().split()[-3:])
            times[(side, i)] = wall
            use[side].append((user + sys_) / wall)
        for (side, i), wall in times.items():
            if side == "old" and ("new", i) in times:
                ratios.append(wall / times[("new", i)])
    if not ratios:
        continue
    print(f"Re = {re}: {len(ratios)} pairs, old / new wall median {statistics.median(ratios):.3f} "
          f"({min(ratios):.3f}-{max(ratios):.3f})")
    for side in ("old", "new"):
        u = sorted(use[side])
        print(f"  {side}: core use (CPU s / wall s, of 2) {u[0]:.3f}-{u[-1]:.3f}, median {statistics.median(u):.3f}")
