#!/usr/bin/env python3
"""Fits the polynomials of nn::Tanh (src/manyworlds/nn/tanh.cc) and prints them as float hex.

    .venv-py/bin/python scripts/fit_tanh_coefficients.py

Two minimax fits of relative error by iteratively reweighted least squares on Chebyshev nodes
(numpy, float64), each then rounded to float32:
  tanh(x) = x + x^3 R(x^2) on [0, 0.5625], R of degree 4;
  exp(r)  = 1 + r + r^2 S(r) on [-ln2/2, ln2/2], S of degree 4.
The C++ kernel's error over every float was then measured against tanh in double precision
(at most 1 ulp); tests/nn/tanh_test.cc repeats that on every 101st float.
"""

import argparse

import numpy as np


def minimax(f, fixed, basis, lo, hi, n=20000, iterations=80):
    """Coefficients c minimising max |fixed(x) + basis(x) @ c - f(x)| / |f(x)| on [lo, hi]."""
    x = lo + (hi - lo) * (1 - np.cos(np.linspace(0, np.pi, n))) / 2
    y, b, w = f(x), basis(x), np.ones(n)
    best = None
    for _ in range(iterations):
        scale = w / np.abs(y)
        c, *_ = np.linalg.lstsq(b * scale[:, None], (y - fixed(x)) * scale, rcond=None)
        err = np.abs((b @ c + fixed(x) - y) / y)
        if best is None or err.max() < best[0]:
            best = (err.max(), c)
        w *= (err / err.mean()) ** 0.3  # weight the worst points up (Lawson's iteration)
        w /= w.mean()
    return best


def main():
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                            formatter_class=argparse.RawDescriptionHelpFormatter,
                            epilog=__doc__.split("\n\n", 1)[1]).parse_args()
    ulp = 2.0 ** -24
    error, r = minimax(np.tanh, lambda x: x,
                       lambda x: x[:, None] ** 3 * (x[:, None] ** 2) ** np.arange(5), 1e-4, 0.5625)
    print(f"R (tanh, max relative error {error / ulp:.3f} ulp before rounding to float):")
    print("  " + ", ".join(float(np.float32(v)).hex() for v in r))
    half_ln2 = np.log(2) / 2
    error, s = minimax(np.exp, lambda t: 1 + t,
                       lambda t: t[:, None] ** 2 * t[:, None] ** np.arange(5), -half_ln2, half_ln2)
    print(f"S (exp, max relative error {error / ulp:.3f} ulp before rounding to float):")
    print("  " + ", ".join(float(np.float32(v)).hex() for v in s))


if __name__ == "__main__":
    main()
