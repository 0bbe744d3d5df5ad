#!/usr/bin/env python3
"""Reference values for tests/materials/test_holzapfel_ogden.cpp (HolzapfelOgden.IndependentValues).

Independent of the C++ code: W of Holzapfel & Ogden 2009 is written on the six entries of a
symmetric C, differentiated by sympy (S = 2 dW/dC, an off-diagonal symbol counted for both
entries), and the incompressible Cauchy stress sigma = F S F^T - p I evaluated at 30 digits.
Default parameters (Pa): the 2009 orthotropic fit. Run: python3 holzapfel_ogden_reference.py
"""
import sympy as sp

a, b, af, bf, as_, bs, afs, bfs = (sp.Rational(59), sp.Rational("8.023"), sp.Rational(18472), sp.Rational("16.026"),
                                   sp.Rational(2481), sp.Rational("11.120"), sp.Rational(216), sp.Rational("11.436"))
c11, c22, c33, c12, c13, c23 = sp.symbols("c11 c22 c33 c12 c13 c23", real=True)
Cs = sp.Matrix([[c11, c12, c13], [c12, c22, c23], [c13, c23, c33]])


def energy(fibre_on, sheet_on):
    W = a / (2 * b) * (sp.exp(b * (c11 + c22 + c33 - 3)) - 1)
    if fibre_on:
        W += af / (2 * bf) * (sp.exp(bf * (c11 - 1) ** 2) - 1)
    if sheet_on:
        W += as_ / (2 * bs) * (sp.exp(bs * (c22 - 1) ** 2) - 1)
    return W + afs / (2 * bfs) * (sp.exp(bfs * c12**2) - 1)


def pk2(F):
    """S = 2 dW/dC at C = F^T F (tension switch from the values of I4f, I4s)."""
    C = F.T * F
    W = energy(C[0, 0] >= 1, C[1, 1] >= 1)
    subs = {c11: C[0, 0], c22: C[1, 1], c33: C[2, 2], c12: C[0, 1], c13: C[0, 2], c23: C[1, 2]}
    sym = [[c11, c12, c13], [c12, c22, c23], [c13, c23, c33]]
    S = sp.zeros(3, 3)
    for i in range(3):
        for j in range(3):
            d = sp.diff(W, sym[i][j]).subs(subs)
            S[i, j] = 2 * d if i == j else d  # the symbol c_ij stands for C_ij and C_ji
    return S


def cauchy_without_p(F):
    return F * pk2(F) * F.T  # J = 1


def show(label, value):
    print(f"{label:40s} {sp.N(value, 20)}")


lam = sp.Rational(11, 10)
F = sp.diag(lam, 1 / sp.sqrt(lam), 1 / sp.sqrt(lam))
s = cauchy_without_p(F)
show("uniaxial 1.1: sigma_ff - sigma_ss", s[0, 0] - s[1, 1])
F = sp.diag(lam, lam, 1 / lam**2)
s = cauchy_without_p(F)
show("equibiaxial 1.1: sigma_ff - sigma_nn", s[0, 0] - s[2, 2])
show("equibiaxial 1.1: sigma_ss - sigma_nn", s[1, 1] - s[2, 2])
g = sp.Rational(1, 2)
names = "fsn"
for i, j in [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)]:
    F = sp.eye(3)
    F[j, i] = g  # mode (ij): the i face sheared in direction j, F = I + gamma e_j (x) e_i
    s = cauchy_without_p(F)
    show(f"shear ({names[i]}{names[j]}) 0.5: sigma_{names[i]}{names[j]}", s[i, j])
