"""NVIDIA Newton's models of our flag: particles, our springs (XPBD, VBD) or a membrane matched to them
(Style3D), pins, and the solvers made on them.

Stiffness matching
------------------
The JSON's springs are used as they are (i, j, k, rest, kind; bend springs have k/10).

XPBD and VBD offer springs, so both get our springs directly: ``ModelBuilder.add_spring(i, j,
ke=k, kd=0, control=0)`` with the rest length overwritten by ours
(``builder.spring_rest_length[s] = rest``; add_spring would take the distance in the start pose).
Same model, same units (N/m): XPBD uses ke as compliance alpha = 1/(ke dt^2)
(xpbd/kernels.py ``solve_springs``); VBD uses force ke (l0 - l)/l (x_i - x_j) and its Hessian
(vbd/particle_vbd_kernels.py ``evaluate_spring_force_and_hessian_both_vertices``). All spring kinds,
bend springs included, so XPBD and VBD solve exactly our energy (with their own iteration).

Style3D has no springs (SolverStyle3D.step evaluates only ``eval_stretch_kernel`` on triangles and
``eval_bend_kernel`` on edges; springs in the model are ignored), so its membrane is matched to our
springs. Its stretch energy per triangle (style3d/kernels.py ``eval_stretch_kernel``, after Baraff and
Witkin) is, with F = [Fu Fv] the deformation gradient in panel (rest) space and A the rest area,

    E = A * ( ku/2 (|Fu| - 1)^2 + kv/2 (|Fv| - 1)^2 + ks/2 (Fu . Fv)^2 ),

so ku, kv are stretch stiffness per unit width (E*t, N/m) along the panel axes u, v, and ks is the
shear stiffness (G*t, N/m). The parameters enter through
``style3d.add_cloth_mesh(..., tri_aniso_ke=wp.vec3(ku, kv, ks))`` -> custom attribute
``style3d:tri_aniso_ke`` -> ``eval_stretch_kernel`` (force) and
``PDMatrixBuilder.add_stretch_constraints`` (builder.py, the constant PD matrix
area * ((ku + ks) dFu dFu + (kv + ks) dFv dFv)). The panel is our rest grid: u along a row (away
from the pole), v along a column, u = c*dx, v = r*dy with dx, dy our structural rest lengths, so the
panel axes are the grid axes.

For a regular grid with structural springs k_s along u (spacing dx, rows dy apart) and along v, and
both diagonals of every cell as shear springs k_d, a uniform small strain e stores per cell
(area dx*dy) the energy sum k l^2 (n.e.n)^2 / 2 over its springs. Per unit area:

    structural along u: k_s dx^2 e_uu^2 / (2 dx dy)  -> E*t along u = ku = k_s * dx / dy
    structural along v:                              -> kv = k_s * dy / dx
    two diagonals, simple shear gamma = 2 e_uv:      -> G*t = ks = 2 k_d dx dy / (dx^2 + dy^2)

which is what the harness uses (``membrane=springs``, the default). On a square grid this is
ku = kv = k_s and ks = k_d: "E*t ~ k for the structural springs, shear ~ k for the shear springs".
It leaves out what the diagonals and bend springs add to the normal stiffness: the diagonals add
2 k_d dx^3 / ((dx^2 + dy^2) dy) to C_uuuu (and a Poisson-like C_uuvv = ks that Baraff-Witkin cannot
hold) and the bend springs (length 2 dx) 4 k_b dx / dy. ``style3d:membrane=full`` adds those two
terms to ku (and the like to kv), i.e. ku = C_uuuu of all our springs. For the study's 17x17 flag
(1.5 m x 1 m, dx = 0.09375, dy = 0.0625, k_s = k_d = 1e4, k_b = 1e3): springs: ku = 1.5e4,
kv = 6.7e3, ks = 9.2e3 N/m; full: ku = 4.2e4, kv = 1.3e4 N/m. Our springs are a stiffer membrane
in pure stretch than ``membrane=springs``, so Style3D's stretch is not comparable one-to-one.

Bending: a skip (bend) spring has no bending stiffness at first order about the flat state (a
curvature kappa shortens it by kappa^2 dx^3 / 3, an energy in kappa^4), so Style3D's bending
(Bergou et al. quadratic model, ``edge_aniso_ke``) is set to 0.
"""

from __future__ import annotations

import numpy as np

from flagstudy.nvidia_newton.case import Case


def grid_spacing(case: Case) -> tuple[float, float]:
    """Rest spacing along a row (u, away from the pole) and along a column (v)."""
    n = case.size
    ij = np.sort(case.spring_ij, axis=1)
    structural = case.spring_kind == "structural"
    du = case.spring_rest[structural & (ij[:, 1] - ij[:, 0] == 1)]
    dv = case.spring_rest[structural & (ij[:, 1] - ij[:, 0] == n)]
    if not len(du) or not len(dv):
        raise ValueError("no structural springs along the grid's rows and columns")
    return float(np.median(du)), float(np.median(dv))


def mean_k(case: Case, kind: str) -> float:
    k = case.spring_k[case.spring_kind == kind]
    return float(k.mean()) if len(k) else 0.0


def membrane_stiffness(case: Case, mode: str) -> tuple[float, float, float]:
    """(ku, kv, ks) of Style3D's membrane matched to our springs (see the module docstring)."""
    dx, dy = grid_spacing(case)
    k_s, k_d, k_b = mean_k(case, "structural"), mean_k(case, "shear"), mean_k(case, "bend")
    diag2 = dx * dx + dy * dy
    ku, kv = k_s * dx / dy, k_s * dy / dx
    ks = 2.0 * k_d * dx * dy / diag2
    if mode == "full":
        ku += 2.0 * k_d * dx**3 / (diag2 * dy) + 4.0 * k_b * dx / dy
        kv += 2.0 * k_d * dy**3 / (diag2 * dx) + 4.0 * k_b * dy / dx
    elif mode != "springs":
        raise ValueError(f"membrane must be 'springs' or 'full', not '{mode}'")
    return ku, kv, ks


def new_builder(case: Case):
    import newton

    return newton.ModelBuilder(up_axis=newton.Axis.Y, gravity=tuple(case.gravity))


def make_kinematic(builder, case: Case) -> None:
    """Pinned particles: mass 0 and not ACTIVE, so that no solver moves them."""
    import newton

    for p in case.pinned:
        builder.particle_mass[p] = 0.0
        builder.particle_flags[p] = int(builder.particle_flags[p]) & ~int(newton.ParticleFlags.ACTIVE)


def build_springs(case: Case, settings: dict, color: bool):
    """Particles and our springs as they are (XPBD, VBD)."""
    import warp as wp

    import newton.utils

    b = new_builder(case)
    for x, m in zip(case.rest, case.masses):
        b.add_particle(pos=wp.vec3(*x), vel=wp.vec3(0.0, 0.0, 0.0), mass=float(m), radius=0.0)
    for (i, j), k, rest in zip(case.spring_ij, case.spring_k, case.spring_rest):
        b.add_spring(int(i), int(j), ke=float(k), kd=0.0, control=0.0)
        b.spring_rest_length[-1] = float(rest)
    make_kinematic(b, case)
    if color:
        edges = wp.array(np.sort(case.spring_ij, axis=1).astype(np.int32), dtype=int, device="cpu")
        b.set_coloring(newton.utils.color_graph(case.n, edges))
    return b.finalize(device="cpu")


def panel_coordinates(case: Case) -> np.ndarray:
    """Our rest grid in 2D: u = column * dx, v = row * dy (row-major, column 0 at the pole)."""
    dx, dy = grid_spacing(case)
    rows, cols = np.divmod(np.arange(case.n), case.size)
    return np.stack([cols * dx, rows * dy], axis=1)


def build_style3d(case: Case, settings: dict):
    import warp as wp

    import newton
    from newton.solvers import style3d

    b = new_builder(case)
    newton.solvers.SolverStyle3D.register_custom_attributes(b)
    panel = panel_coordinates(case)
    tris = case.triangles.copy()
    p0, p1, p2 = panel[tris[:, 0]], panel[tris[:, 1]], panel[tris[:, 2]]
    signed = (p1 - p0)[:, 0] * (p2 - p0)[:, 1] - (p1 - p0)[:, 1] * (p2 - p0)[:, 0]
    tris[signed < 0] = tris[signed < 0][:, [0, 2, 1]]  # Style3D drops triangles of negative panel area
    ku, kv, ks = membrane_stiffness(case, settings["membrane"])
    style3d.add_cloth_mesh(
        b,
        pos=wp.vec3(0.0, 0.0, 0.0),
        rot=wp.quat_identity(),
        vel=wp.vec3(0.0, 0.0, 0.0),
        vertices=case.rest.tolist(),
        indices=tris.reshape(-1).tolist(),
        density=0.0,
        panel_verts=panel.tolist(),
        tri_aniso_ke=wp.vec3(ku, kv, ks),
        edge_aniso_ke=wp.vec3(0.0, 0.0, 0.0),
        tri_kd=0.0,
        edge_kd=0.0,
        particle_radius=0.0,
    )
    if len(b.tri_indices) != len(tris):
        raise ValueError(f"Style3D kept {len(b.tri_indices)} of {len(tris)} triangles (degenerate panel triangles)")
    b.particle_mass[:] = case.masses.tolist()
    make_kinematic(b, case)
    return b.finalize(device="cpu")


def make_vbd(model, settings: dict):
    import newton

    return newton.solvers.SolverVBD(model, iterations=settings["iterations"])


def make_xpbd(model, settings: dict):
    import newton

    return newton.solvers.SolverXPBD(model, iterations=settings["iterations"])


def make_style3d(model, settings: dict):
    import newton

    solver_cls = newton.solvers.SolverStyle3D
    config = solver_cls.Config(iterations=settings["iterations"], linear_iterations=settings["linear_iterations"])
    solver = solver_cls(model, config=config)
    solver.collision = None  # no collisions (the solver's documented switch)
    return solver
