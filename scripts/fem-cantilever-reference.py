#!/usr/bin/env python3
"""3D FEM reference of the cantilever of issue 13 (made independently of perifrac).

A cantilever L × h × h along x, x ∈ [0, L], its whole end face x = 0 fixed (u = 0),
E = 2e8 Pa, ν = 0.25, ρ = 1000 kg/m³, h = 0.1 m, L/h = 5 and 10, small-strain linear
elasticity with triquadratic 27-node hexahedra (scikit-fem `ElementHex2` on a uniform
`MeshHex`, n elements across, n L/h along). It prints, for n = 2, 4, 6, 8, ...:

* the static tip deflection under gravity g = 9.81 m/s² along −y: the mean of −u_y over
  the free end face x = L (∫ u_y dA / h², a facet integral);
* the first bending frequency f₁ = ω₁/2π from the generalised eigenproblem
  K u = ω² M u (consistent mass; the section is square, so the two bending planes
  share f₁).

Both converge monotonically as n grows (from the stiff side); the numbers kept in
perifrac's tests (`sim/tests/bending.rs`) are those of n = 10 (`... 4 6 8 10`, 16 min on
2 cores), whose change from n = 8 is +0.015% / −0.007% (L/h = 5) and +0.007% /
−0.004% (L/h = 10): converged to better than 0.1%. Both scale exactly: deflection
∝ ρg/E, f₁ ∝ √(E/ρ)/h for fixed L/h and ν. `... free n ...` prints the first bending
frequency of the same beams with both ends free (no clamp).

    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install scikit-fem numpy scipy
    /tmp/venv/bin/python scripts/fem-cantilever-reference.py [n ...]
    /tmp/venv/bin/python scripts/fem-cantilever-reference.py free [n ...]
"""

import sys

import numpy as np
from scipy.sparse.linalg import eigsh, spsolve
from skfem import (Basis, BilinearForm, ElementHex2, ElementVector, FacetBasis,
                   LinearForm, MeshHex, condense, Functional)
from skfem.models.elasticity import lame_parameters, linear_elasticity

E, NU, RHO, G, H = 2.0e8, 0.25, 1000.0, 9.81, 0.1


def solve(slender, n):
    length = slender * H
    mesh = MeshHex.init_tensor(
        np.linspace(0.0, length, slender * n + 1),
        np.linspace(-H / 2, H / 2, n + 1),
        np.linspace(-H / 2, H / 2, n + 1),
    ).with_boundaries({
        "clamp": lambda x: np.isclose(x[0], 0.0),
        "tip": lambda x: np.isclose(x[0], length),
    })
    element = ElementVector(ElementHex2())
    basis = Basis(mesh, element, intorder=5)
    stiffness = linear_elasticity(*lame_parameters(E, NU)).assemble(basis)

    @BilinearForm
    def mass(u, v, w):
        return RHO * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2])

    @LinearForm
    def gravity(v, w):
        return -RHO * G * v[1]

    m = mass.assemble(basis)
    f = gravity.assemble(basis)
    fixed = basis.get_dofs("clamp").all()
    u = np.zeros(basis.N)
    free = np.setdiff1d(np.arange(basis.N), fixed)
    u[free] = spsolve(*condense(stiffness, f, D=fixed)[:2])
    tip_basis = FacetBasis(mesh, element, facets=mesh.boundaries["tip"], intorder=5)

    @Functional
    def uy(w):
        return w["u"][1]

    deflection = -uy.assemble(tip_basis, u=tip_basis.interpolate(u)) / H**2
    kk = stiffness[free][:, free]
    mm = m[free][:, free]
    w2 = eigsh(kk, k=1, M=mm, sigma=0.0, which="LM", return_eigenvectors=False)
    f1 = np.sqrt(w2.min()) / (2.0 * np.pi)
    return deflection, f1, basis.N


def free_free(slender, n):
    """First bending frequency (Hz) of the same beam with both ends free."""
    length = slender * H
    mesh = MeshHex.init_tensor(
        np.linspace(0.0, length, slender * n + 1),
        np.linspace(-H / 2, H / 2, n + 1),
        np.linspace(-H / 2, H / 2, n + 1),
    )
    basis = Basis(mesh, ElementVector(ElementHex2()), intorder=5)
    stiffness = linear_elasticity(*lame_parameters(E, NU)).assemble(basis)

    @BilinearForm
    def mass(u, v, w):
        return RHO * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2])

    w2 = eigsh(stiffness, k=8, M=mass.assemble(basis), sigma=-1.0, which="LM",
               return_eigenvectors=False)
    w2 = np.sort(w2)
    # Six rigid-body modes (ω² ≈ 0), then the two bending modes of the square section.
    return np.sqrt(w2[6]) / (2.0 * np.pi)


def main():
    if sys.argv[1:2] == ["free"]:
        for slender in (5, 10):
            for n in [int(a) for a in sys.argv[2:]] or [2, 4, 6]:
                print(f"free-free L/h = {slender:2d}, n = {n:2d}: f1 = {free_free(slender, n):.5f} Hz",
                      flush=True)
        return
    ns = [int(a) for a in sys.argv[1:]] or [2, 4, 6, 8]
    for slender in (5, 10):
        prev = None
        for n in ns:
            d, f1, dofs = solve(slender, n)
            change = "" if prev is None else (
                f"  (change {100 * (d / prev[0] - 1):+.3f}%, {100 * (f1 / prev[1] - 1):+.3f}%)")
            print(f"L/h = {slender:2d}, n = {n:2d} ({dofs:7d} dofs): tip deflection "
                  f"{d:.6e} m, f1 = {f1:.5f} Hz{change}", flush=True)
            prev = (d, f1)


if __name__ == "__main__":
    main()
