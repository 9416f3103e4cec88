#!/usr/bin/env python3
"""The L_inf error a viscosity lambda nu instead of nu makes in plane
Poiseuille start-up from rest, against the exact series, in units of the
steady centre-line speed U, at t nu / B^2 = TAU (bench/peers/ACCURACY.md).

With nu_eff = lambda nu the SPH flow is the series with nu replaced:
u / U = (1 / lambda) [4 s (1 - s) - sum_k 32 / (pi^3 k^3) sin(k pi s)
exp(-k^2 pi^2 lambda tau / 4)], s = (y + B) / 2B, k odd: no wall model,
no resolution, only the viscosity. The error is sampled at 999 points.

usage: scripts/startup_error.py LAMBDA [TAU ...]   (default TAU: 0.25 0.5 1 40)
"""
import math
import sys


def u(s, tau, lam):
    v = 4 * s * (1 - s)
    for n in range(400):
        k = 2 * n + 1
        v -= 32 / (math.pi ** 3 * k ** 3) * math.sin(k * math.pi * s) * math.exp(-k * k * math.pi ** 2 * lam * tau / 4)
    return v / lam


def main():
    lam = float(sys.argv[1])
    taus = [float(t) for t in sys.argv[2:]] or [0.25, 0.5, 1.0, 40.0]
    for tau in taus:
        e = max(abs(u(i / 1000, tau, lam) - u(i / 1000, tau, 1.0)) for i in range(1, 1000))
        print(f"lambda {lam:.6f}, t nu/B^2 = {tau:g}: L_inf / U = {e:.4e}")


if __name__ == "__main__":
    main()
