"""The clamped plate's lowest eigenvalues computed by GetFEM on PlateImpact's structured meshes.

Usage: getfem_spectrum.py ELEMENT NX NY LX LY D RHO_E NU MODES SIDE...
ELEMENT is argyris or fvs; each SIDE is xmin, xmax, ymin or ymax (a whole clamped edge), or
NAME:FROM:TO for the segment FROM <= t <= TO of that edge, t the coordinate along it. Prints
one line of the MODES lowest omega^2 (rad^2/s^2), space separated.

Independent of PlateImpact but for the mesh layout (vertex (i, j) at (i Lx/NX, j Ly/NY); each
cell cut by its diagonal from (x_i, y_j) to (x_{i+1}, y_{j+1}) for triangles): GetFEM's own
Argyris triangle (FEM_ARGYRIS) or reduced Fraeijs de Veubeke-Sanders quadrilateral
(FEM_REDUCED_QUADC1_COMPOSITE), its quadrature, its generic assembly of the Kirchhoff-Love forms,
and the clamp as the kernel of the boundary form B(u, v) = integral over the clamped edges of
u v + L^2 grad u . grad v, which vanishes exactly on the fields with u = 0 and grad u = 0 there.
"""

import sys

import getfem as gf
import numpy as np
import scipy.linalg


def main():
    element, nx, ny = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    lx, ly, d, rho_e, nu = (float(v) for v in sys.argv[4:9])
    modes = int(sys.argv[9])
    sides = sys.argv[10:]
    mesh = gf.Mesh("empty", 2)

    def point(i, j):
        return [i * lx / nx, j * ly / ny]

    for j in range(ny):
        for i in range(nx):
            a, b, c, e = point(i, j), point(i + 1, j), point(i, j + 1), point(i + 1, j + 1)
            if element == "argyris":
                mesh.add_convex(gf.GeoTrans("GT_PK(2,1)"), np.array([a, b, e]).T)
                mesh.add_convex(gf.GeoTrans("GT_PK(2,1)"), np.array([a, e, c]).T)
            else:
                # GetFEM's Q1 vertex order: (0,0), (1,0), (0,1), (1,1).
                mesh.add_convex(gf.GeoTrans("GT_QK(2,1)"), np.array([a, b, c, e]).T)
    if element == "argyris":
        fem, im = "FEM_ARGYRIS", "IM_TRIANGLE(13)"
    else:
        fem, im = "FEM_REDUCED_QUADC1_COMPOSITE", "IM_QUADC1_COMPOSITE(IM_TRIANGLE(13))"
    mf = gf.MeshFem(mesh, 1)
    mf.set_fem(gf.Fem(fem))
    mim = gf.MeshIm(mesh, gf.Integ(im))
    # The clamped edges as a boundary region: the outer faces whose centre lies on a named side.
    faces = mesh.outer_faces()
    centres = []
    for k in range(faces.shape[1]):
        pts = mesh.pts(mesh.pid_in_faces(faces[:, k : k + 1]))
        centres.append(pts.mean(axis=1))
    on_side = {
        "xmin": lambda p: abs(p[0]) < 1e-9 * lx,
        "xmax": lambda p: abs(p[0] - lx) < 1e-9 * lx,
        "ymin": lambda p: abs(p[1]) < 1e-9 * ly,
        "ymax": lambda p: abs(p[1] - ly) < 1e-9 * ly,
    }

    def clamped(p, spec):
        name, *ends = spec.split(":")
        along = p[1] if name in ("xmin", "xmax") else p[0]
        # A face is clamped when its centre lies in the segment, ends included (to round-off),
        # as plate.clamp decides on the mesh.
        tolerance = 1e-9 * max(lx, ly)
        inside = not ends or float(ends[0]) - tolerance <= along <= float(ends[1]) + tolerance
        return on_side[name](p) and inside

    chosen = [k for k, p in enumerate(centres) if any(clamped(p, s) for s in sides)]
    mesh.set_region(1, faces[:, chosen])
    md = gf.Model("real")
    md.add_fem_variable("u", mf)
    md.add_initialized_data("D", [d])
    md.add_initialized_data("nu", [nu])
    md.add_initialized_data("rho_e", [rho_e])
    md.add_initialized_data("L2", [lx * lx])

    def dense(expression, region=-1):
        return gf.asm_generic(mim, 2, expression, region, md).full()

    stiffness = dense(
        "D*((1-nu)*(Hess_Test_u:Hess_Test2_u) + nu*Trace(Hess_Test_u)*Trace(Hess_Test2_u))"
    )
    mass = dense("rho_e*Test_u*Test2_u")
    clamp = dense("Test_u*Test2_u + L2*(Grad_Test_u.Grad_Test2_u)", 1)
    # Jacobi scaling by the mass diagonal: GetFEM's derivative dofs are unscaled (a second
    # derivative's basis function is of size h^2), which leaves M and K with condition numbers
    # near 1e13; scaled, the eigenvalues are the same and lose far less to round-off.
    scale = 1.0 / np.sqrt(np.diag(mass))
    stiffness, mass, clamp = (scale[:, None] * a * scale[None, :] for a in (stiffness, mass, clamp))
    clamp = 0.5 * (clamp + clamp.T)
    values, vectors = np.linalg.eigh(clamp)
    kernel = vectors[:, values < 1e-11 * values.max()]
    k = kernel.T @ stiffness @ kernel
    m = kernel.T @ mass @ kernel
    omega_squared = scipy.linalg.eigh(0.5 * (k + k.T), 0.5 * (m + m.T), eigvals_only=True)
    print(" ".join(repr(float(w)) for w in omega_squared[:modes]))


main()
