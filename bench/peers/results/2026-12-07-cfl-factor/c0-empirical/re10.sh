#!/usr/bin/env bash
cd "$(dirname "$0")"
for round in 1 2; do
  for f in 0.5 1.0; do
    /usr/bin/time -f "%e wall %U user %S sys" -o time-re10-cfl$f-r$round.txt "${SHEARSPH:-shearsph}" c0 --kernel monaghan --n 10 --re 10 --empirical --json --quiet --cfl $f > c0-re10-cfl$f-r$round.json 2> err-re10-cfl$f-r$round.txt
  done
done
