#!/usr/bin/env bash
cd "$(dirname "$0")"
for round in 1 2; do
  for f in 0.5 0.75 1.0; do
    /usr/bin/time -f "%e wall %U user %S sys" -o time-re1-cfl$f-r$round.txt "${SHEARSPH:-shearsph}" c0 --kernel monaghan --n 10 --re 1 --empirical --json --quiet --cfl $f > c0-re1-cfl$f-r$round.json 2> err-re1-cfl$f-r$round.txt
  done
done
