#!/usr/bin/env python3
"""The stable step of a brittle frame, four ways (issue 38, docs/performance.md "The step's bound").

    python3 bench/step/spectrum.py FRAME.vtu [--E 32e9 --nu 0.2 --rho 2450 --h 0.5e-3]

FRAME.vtu: a frame a run wrote (`--set output.frame_times=0` for the initial grid; a later
frame has the split nodes). Linear elasticity at the frame's positions, lumped masses from
the elements (rho V / 4 to each corner, so a split node's daughters carry their own cells'),
no viscosity. Prints, in units of h / c_p:
  - the altitude bound at cfl 1 (brittle's default: min over elements of altitude / c_p);
  - the exact element limit 2 / omega_e (omega_e^2 = largest eigenvalue of K_e / (rho V / 4));
  - the grid's limit 2 / omega_max of the assembled M^-1 K (ARPACK, scipy.sparse.linalg.eigsh);
  - the nodal bound (run.step_bound = nodal at cfl 1, undamped): max_i sum_e k_e / m_i.
Needs python3-numpy, python3-scipy and python3-vtk9 (Debian 12).
"""
import argparse

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
import vtk
from vtk.util.numpy_support import vtk_to_numpy

ap = argparse.ArgumentParser()
ap.add_argument("frame")
ap.add_argument("--E", type=float, default=32e9)
ap.add_argument("--nu", type=float, default=0.2)
ap.add_argument("--rho", type=float, default=2450.0)
ap.add_argument("--h", type=float, default=0.5e-3, help="the length of h / c_p [m]")
a = ap.parse_args()
lam = a.E * a.nu / ((1 + a.nu) * (1 - 2 * a.nu))
mu = a.E / (2 * (1 + a.nu))
cp = np.sqrt((lam + 2 * mu) / a.rho)

r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(a.frame)
r.Update()
g = r.GetOutput()
X = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4)
n, ne = len(X), len(conn)
P = X[conn]
A = np.concatenate([np.ones((ne, 4, 1)), P], axis=2)
G = np.transpose(np.linalg.inv(A)[:, 1:, :], (0, 2, 1))  # ne x 4 x 3 shape-function gradients
V = np.abs(np.linalg.det(A)) / 6
B = np.zeros((ne, 6, 12))
for k in range(4):
    gx, gy, gz = G[:, k, 0], G[:, k, 1], G[:, k, 2]
    B[:, 0, 3 * k], B[:, 1, 3 * k + 1], B[:, 2, 3 * k + 2] = gx, gy, gz
    B[:, 3, 3 * k], B[:, 3, 3 * k + 1] = gy, gx
    B[:, 4, 3 * k + 1], B[:, 4, 3 * k + 2] = gz, gy
    B[:, 5, 3 * k], B[:, 5, 3 * k + 2] = gz, gx
D = np.zeros((6, 6))
D[:3, :3] = lam
D[range(3), range(3)] += 2 * mu
D[3:, 3:] = np.eye(3) * mu
Ke = V[:, None, None] * np.einsum("eia,ij,ejb->eab", B, D, B)
me = a.rho * V / 4
k_e = np.linalg.eigvalsh(Ke)[:, -1]
dt_exact = 2 / np.sqrt(k_e / me)
faces = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]
largest = np.max([np.linalg.norm(np.cross(P[:, f[1]] - P[:, f[0]], P[:, f[2]] - P[:, f[0]]), axis=1) / 2
                  for f in faces], axis=0)
dt_alt = 3 * V / largest / cp
dof = (3 * conn[:, :, None] + np.arange(3)).reshape(ne, 12)
K = sp.csr_matrix((Ke.ravel(), (np.repeat(dof, 12, axis=1).ravel(), np.tile(dof, (1, 12)).ravel())),
                  shape=(3 * n, 3 * n))
m = np.zeros(n)
np.add.at(m, conn.ravel(), np.repeat(me, 4))
s = sp.diags(1 / np.sqrt(np.repeat(m, 3)))
w2 = sla.eigsh(s @ K @ s, k=1, which="LA", return_eigenvectors=False, tol=1e-6)[0]
dt_grid = 2 / np.sqrt(w2)
L = np.zeros(n)
np.add.at(L, conn.ravel(), np.repeat(k_e, 4))
dt_nodal = 2 / np.sqrt((L / m).max())
u = cp / a.h
print(f"{a.frame}: {ne} tets, {n} nodes; in h / c_p, h = {a.h * 1e3:g} mm, c_p = {cp:.0f} m/s")
print(f"  altitude bound (cfl 1)      {dt_alt.min() * u:.3f}")
print(f"  exact element limit         {dt_exact.min() * u:.3f} (median element {np.median(dt_exact) * u:.3f});"
      f" exact / altitude {np.min(dt_exact / dt_alt):.3f}-{np.max(dt_exact / dt_alt):.3f}")
print(f"  the grid's limit            {dt_grid * u:.3f}")
print(f"  nodal bound (cfl 1)         {dt_nodal * u:.3f}")
