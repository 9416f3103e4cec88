#!/usr/bin/env bash
# Rerun every measured answer docs/answer.md holds, into OUT (a new dated
# folder beside the others in docs/answer/), with the commands the docs give:
#   OUT/monaghan-n10-re{1,10}.txt   c0 --kernel monaghan --n 10 --re R --empirical
#   OUT/monaghan-n10-re1-tolerance.txt   the same at Re = 1 with --tolerance 0.01
#                                   (the c0 the disordered law gives a density
#                                   tolerance alone, docs/answer.md)
#   OUT/kernels/K-L.txt             c0 --kernel K --lattice L --h-over-d 1 --n 10
#                                      --re 1 --empirical --no-rules --quiet
#                                   (every kernel on both lattices)
#   OUT/kernels/monaghan-square-re10.txt   the same at Re = 10 (docs/validation.md)
# each beside a .time file (wall and user CPU seconds of the whole process).
# A change that moves a disordered run's bits (the step's order of summation,
# the lists, the time step) moves these answers: they are rerun with it.
#
#   scripts/rerun-answers.sh docs/answer/YYYY-MM-DD-what [path/to/shearsph]
#   DRY=1 scripts/rerun-answers.sh OUT      # print the commands only
set -euo pipefail
out=${1:?usage: scripts/rerun-answers.sh OUT_DIR [SHEARSPH]}
bin=${2:-target/release/shearsph}
run() {
  local file=$1
  shift
  if [ -n "${DRY:-}" ]; then
    echo "$bin $* > $file.txt"
    return
  fi
  /usr/bin/time -f 'wall %e s, cpu %U s' -o "$file.time" "$bin" "$@" > "$file.txt"
}
[ -n "${DRY:-}" ] || mkdir -p "$out/kernels"
for re in 1 10; do
  run "$out/monaghan-n10-re$re" c0 --kernel monaghan --n 10 --re "$re" --empirical --quiet
done
run "$out/monaghan-n10-re1-tolerance" c0 --kernel monaghan --n 10 --re 1 --empirical \
  --tolerance 0.01 --quiet
for k in composite monaghan morris wendland_c2; do
  for lattice in triangular square; do
    run "$out/kernels/$k-$lattice" c0 --kernel "$k" --lattice "$lattice" --h-over-d 1 \
      --n 10 --re 1 --empirical --no-rules --quiet
  done
done
run "$out/kernels/monaghan-square-re10" c0 --kernel monaghan --lattice square --h-over-d 1 \
  --n 10 --re 10 --empirical --no-rules --quiet
