"""Finite-element limit analysis: geometry and mesh, strength domains, operators, problems, the
kinematic (upper) and static (lower) bound programs and their bracket."""
