"""Static (lower-bound) finite-element limit analysis with linear equilibrium triangles.

The stress field σ = (σ_x, σ_z, τ_xz) is linear on each triangle and discontinuous between
triangles: three stress vectors per triangle, one at each vertex. A field is *statically
admissible* for the live multiplier λ when

- equilibrium holds inside every triangle (div σ is constant there, so two equations each):
      ∂σ_x/∂x + ∂τ_xz/∂z + λ b_x + b⁰_x = 0,   ∂τ_xz/∂x + ∂σ_z/∂z + λ b_z + b⁰_z = 0,
  with b the live and b⁰ the dead body force per unit volume [N/m³];
- the traction t = σ n is continuous across every interior edge (t is linear along an edge,
  so equality at both ends: four equations per edge);
- t = λ t_live + t_dead (+ Σ ν_k t_k of the ties, 0 <= ν_k <= 1, ``Problem.ties``) on free
  boundaries, for every traction component whose displacement component is not supported (a
  roller u_x = 0 leaves t_x free and imposes t_z);
- σ ∈ G at the three vertices of every triangle, which for a convex G and a linear σ means
  σ ∈ G everywhere in the triangle;
- regions of ``strength.Rigid`` carry no stress: each connected one is a body whose resultant
  force and moment vanish (body forces, boundary tractions, the tractions of the neighbouring
  triangles, reactions, and joint forces including concentrated ones at the joint's ends).


By the static theorem of limit analysis the largest such λ, λ⁻, is a lower bound of the
collapse multiplier (for the discrete problem as posed: see docs/static.md on truncated
domains). The program is a conic program, max λ over (σ, λ, y) with the strength condition
written through each domain's ``static_cone()`` (σ ∈ G ⇔ ∃y: Aσ + Dy + e ∈ K), assembled
directly as one sparse matrix for Clarabel: no per-element Python objects and no loop over
elements or edges. Modules: ``assembly`` (the rows, step by step), ``bodies`` (rigid bodies and
the forces on them), ``program`` (``solve_static``: the outline, the solve and its read-back),
``solution`` (``StaticSolution``).
"""

from .assembly import edge_tables, triangle_gradients
from .bodies import rigid_bodies
from .program import solve_static
from .solution import StaticSolution, attach_cell_fields

__all__ = ["StaticSolution", "attach_cell_fields", "solve_static", "triangle_gradients",
           "edge_tables", "rigid_bodies"]
