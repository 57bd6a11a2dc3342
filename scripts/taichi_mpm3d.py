"""The Taichi side of scripts/taichi-compare.sh: 3D MLS-MPM (Hu et al. 2018) on
Taichi's CPU backend, equivalent to perifrac's throughput benchmark
(sim/tests/mpm.rs, throughput): quadratic B-splines, APIC, fixed corotated
elasticity (ti.svd), f32, one dense grid, gravity and a slip ground. A block of
0.4 x 0.2 x 0.16 m at 8 particles a cell of side `dx`, E = 1e5 Pa, nu = 0.3,
rho = 1000, dt at the same elastic bound (0.6 dx / c_p, times 0.9).

Prints one line: particles, steps, particle-steps/s (after a warm-up that
compiles the kernels)."""

import sys
import time

import taichi as ti

dx = float(sys.argv[1]) if len(sys.argv) > 1 else 0.01
steps = int(sys.argv[2]) if len(sys.argv) > 2 else 20
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
ti.init(arch=ti.cpu, default_fp=ti.f32, cpu_max_num_threads=threads, random_seed=1)

size = (0.4, 0.2, 0.16)
per_axis = [int(round(s / dx)) * 2 for s in size]
n = per_axis[0] * per_axis[1] * per_axis[2]
inv_dx = 1.0 / dx
# The grid covers the block with a margin of 8 cells and 24 cells above it.
n_grid = [int(round(s / dx)) + 16 for s in size]
n_grid[1] += 16
origin = (-8 * dx, -8 * dx, -8 * dx)
rho, E, nu = 1000.0, 1e5, 0.3
mu, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
c_p = ((lam + 2 * mu) / rho) ** 0.5
dt = 0.9 * 0.6 * dx / c_p
p_vol = (dx * 0.5) ** 3
p_mass = rho * p_vol
gravity = -9.81

x = ti.Vector.field(3, ti.f32, n)
v = ti.Vector.field(3, ti.f32, n)
C = ti.Matrix.field(3, 3, ti.f32, n)
F = ti.Matrix.field(3, 3, ti.f32, n)
grid_v = ti.Vector.field(3, ti.f32, n_grid)
grid_m = ti.field(ti.f32, n_grid)


@ti.kernel
def seed():
    for i, j, k in ti.ndrange(per_axis[0], per_axis[1], per_axis[2]):
        p = (k * per_axis[1] + j) * per_axis[0] + i
        jitter = ti.Vector([ti.random(), ti.random(), ti.random()]) - 0.5
        x[p] = (ti.Vector([i, j, k]) + 0.5 + 0.5 * jitter) * dx * 0.5 - ti.Vector(origin)
        v[p] = ti.Vector([0.0, 0.0, 0.0])
        F[p] = ti.Matrix.identity(ti.f32, 3)
        C[p] = ti.Matrix.zero(ti.f32, 3, 3)


@ti.kernel
def substep():
    for I in ti.grouped(grid_m):
        grid_v[I] = ti.Vector.zero(ti.f32, 3)
        grid_m[I] = 0.0
    ti.loop_config(block_dim=64)
    for p in x:
        Xp = x[p] * inv_dx
        base = int(Xp - 0.5)
        fx = Xp - base
        w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
        U, sig, V = ti.svd(F[p])
        J = sig[0, 0] * sig[1, 1] * sig[2, 2]
        R = U @ V.transpose()
        stress = 2 * mu * (F[p] - R) @ F[p].transpose() + ti.Matrix.identity(ti.f32, 3) * lam * J * (J - 1)
        stress = (-dt * p_vol * 4 * inv_dx * inv_dx) * stress
        affine = stress + p_mass * C[p]
        for offset in ti.static(ti.grouped(ti.ndrange(3, 3, 3))):
            dpos = (offset - fx) * dx
            weight = w[offset[0]][0] * w[offset[1]][1] * w[offset[2]][2]
            grid_v[base + offset] += weight * (p_mass * v[p] + affine @ dpos)
            grid_m[base + offset] += weight * p_mass
    for I in ti.grouped(grid_m):
        if grid_m[I] > 0:
            grid_v[I] /= grid_m[I]
            grid_v[I][1] += dt * gravity
            # The ground y = 0 (node 8 from the grid's origin): slip, no penetration.
            if I[1] <= 8 and grid_v[I][1] < 0:
                grid_v[I][1] = 0
    ti.loop_config(block_dim=64)
    for p in x:
        Xp = x[p] * inv_dx
        base = int(Xp - 0.5)
        fx = Xp - base
        w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
        new_v = ti.Vector.zero(ti.f32, 3)
        new_C = ti.Matrix.zero(ti.f32, 3, 3)
        for offset in ti.static(ti.grouped(ti.ndrange(3, 3, 3))):
            dpos = (offset - fx) * dx
            weight = w[offset[0]][0] * w[offset[1]][1] * w[offset[2]][2]
            g_v = grid_v[base + offset]
            new_v += weight * g_v
            new_C += 4 * inv_dx * inv_dx * weight * g_v.outer_product(dpos)
        v[p] = new_v
        C[p] = new_C
        x[p] += dt * new_v
        F[p] = (ti.Matrix.identity(ti.f32, 3) + dt * new_C) @ F[p]


seed()
for _ in range(3):
    substep()
ti.sync()
start = time.perf_counter()
for _ in range(steps):
    substep()
ti.sync()
wall = time.perf_counter() - start
print(f"taichi {n} particles, {steps} steps, {threads} threads: {n * steps / wall:.4e} particle-steps/s")
