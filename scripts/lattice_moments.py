#!/usr/bin/env python3
"""Lattice sums of the SPH operators on the perfect lattice, against their
continuum values, for every shipped kernel x discretisation (bench/peers/ACCURACY.md).

For a particle in the bulk of the lattice (neighbours on every side, self
included in the density), with A = d dy the area per particle (m / rho0),
F(r) = W'(r) / r, and sums over every other lattice site j at r_j = (x_j, y_j):

  sigma = A sum_all W(r_j)             the summation density / rho0 = 1 + eps(0)
  L_yy  = -A sum y_j^2 F(r_j)          the Morris Laplacian's second moment: the
                                       operator 2 sum V_j (u_i - u_j) F applied to
                                       u = y^2 / 2 gives L_yy (continuum 1); it is
                                       also the yy entry of -sum V_j r_j (x) grad W,
                                       the matrix a kernel-gradient correction inverts
  L_xx  = -A sum x_j^2 F(r_j)          the same along x (continuum 1)
  L_av  = -4 A sum x_j^2 y_j^2 / r_j^2 F(r_j)
                                       Monaghan's artificial viscosity in shear: over
                                       approaching pairs only it acts as a kinematic
                                       viscosity alpha c0 h L_av / 16 (continuum L_av = 1;
                                       over all pairs alpha c0 h / 8, Monaghan 2005)

The kernels are written out here from kernels/*.toml (2D, q = r / h); the sums
are exact to double rounding (finite sums), printed to 6 digits. Usage:
  python3 scripts/lattice_moments.py
"""
import math

PI = math.pi


def piecewise(pieces):
    def f(q):
        for to, g in pieces:
            if q <= to:
                return g(q)
        return 0.0
    return f


def deriv(w):
    # Central difference of a polynomial piece (W' only enters as a check
    # where no gradient is given; the shipped kernels' W' is written out).
    return lambda q, e=1e-6: (w(q + e) - w(q - e)) / (2 * e)


KERNELS = {
    # name: (support R, scale, w(q), w'(q))
    "composite": (
        1,
        15 / 13,
        piecewise([(1, lambda q: (1 - q * q) ** 2 * (1 - (4 - 52 / (5 * PI)) * q * q))]),
        # (22b), not the derivative of (22a), with its own scale
        piecewise([(1, lambda q: 264 / (665 * PI) * (22 * q - 25) / (15 / 13))]),
    ),
    "monaghan": (
        2,
        15 / (7 * PI),
        piecewise([(1, lambda q: 2 / 3 - q * q + q ** 3 / 2), (2, lambda q: (2 - q) ** 3 / 6)]),
        piecewise([(1, lambda q: -2 * q + 1.5 * q * q), (2, lambda q: -0.5 * (2 - q) ** 2)]),
    ),
    "morris": (
        3,
        7 / (478 * PI),
        piecewise([
            (1, lambda q: (3 - q) ** 5 - 6 * (2 - q) ** 5 + 15 * (1 - q) ** 5),
            (2, lambda q: (3 - q) ** 5 - 6 * (2 - q) ** 5),
            (3, lambda q: (3 - q) ** 5),
        ]),
        piecewise([
            (1, lambda q: -5 * (3 - q) ** 4 + 30 * (2 - q) ** 4 - 75 * (1 - q) ** 4),
            (2, lambda q: -5 * (3 - q) ** 4 + 30 * (2 - q) ** 4),
            (3, lambda q: -5 * (3 - q) ** 4),
        ]),
    ),
    "wendland_c2": (
        2,
        7 / (4 * PI),
        piecewise([(2, lambda q: (1 - q / 2) ** 4 * (2 * q + 1))]),
        piecewise([(2, lambda q: -5 * q * (1 - q / 2) ** 3)]),
    ),
}

DISCRETISATIONS = [
    ("triangular", 1.0),
    ("triangular", 1.3),
    ("square", 1.0),
    ("square", 1.3),
    ("square", 1.7),
]


def sites(lattice, hd, support):
    """Lattice sites within R h of the origin, d = 1, h = hd."""
    dy = math.sqrt(3) / 2 if lattice == "triangular" else 1.0
    reach = support * hd
    rows = int(reach / dy) + 2
    cols = int(reach) + 2
    out = []
    for j in range(-rows, rows + 1):
        shift = 0.5 if (lattice == "triangular" and j % 2) else 0.0
        for i in range(-cols - 1, cols + 2):
            x, y = i + shift, j * dy
            if math.hypot(x, y) <= reach * (1 + 1e-12):  # the support closed: (22b) is not 0 at q = 1
                out.append((x, y))
    return dy, out


def moments(name, lattice, hd):
    support, scale, w, dw = KERNELS[name]
    dy, pts = sites(lattice, hd, support)
    area = dy  # d = 1
    h = hd
    sigma = lyy = lxx = lav = 0.0
    for x, y in pts:
        r = math.hypot(x, y)
        q = r / h
        sigma += scale / h ** 2 * w(q)
        if r == 0:
            continue
        f = scale / h ** 3 * dw(q) / r  # W'(r) / r
        lyy -= y * y * f
        lxx -= x * x * f
        lav -= 4 * x * x * y * y / (r * r) * f
    return sigma * area, lyy * area, lxx * area, lav * area


def main():
    print("kernel        lattice      h/d   1+eps(0)   L_yy       L_xx       L_av     "
          "L_yy/(1+eps)^2  L_av/(1+eps)")
    for name in KERNELS:
        for lattice, hd in DISCRETISATIONS:
            s, lyy, lxx, lav = moments(name, lattice, hd)
            print(f"{name:13s} {lattice:11s} {hd:4.2f}  {s:.6f}  {lyy:.6f}  {lxx:.6f}  "
                  f"{lav:.6f}  {lyy / s ** 2:.6f}        {lav / s:.6f}")


if __name__ == "__main__":
    main()
