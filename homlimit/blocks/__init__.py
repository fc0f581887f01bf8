"""The T-section as rigid blocks: the discrete model beside the homogenised continuum (issue 17).

    from homlimit.blocks import analyse_blocks
    an = analyse_blocks(case)                 # whole wall + h-scan + critical height
    an.files(), an.summary()                  # name → data of its files; plain data for JSON

Modules: ``geometry`` (the running-bond T-section and its interfaces), ``limit`` (one sparse
LP through cvxpy + Clarabel, associative or non-associative friction, the static dual),
``impulse`` (eq. 7 for the discrete mechanism), ``output`` (VTU, contact records, PNG), ``studies``
(h-scan, homogenisation study, Table 1 with the discrete column). Write-up: docs/blocks.md.
"""

from .geometry import (
                       Assembly,
                       Interfaces,
                       find_interfaces,
                       from_rectangles,
                       running_bond_panel,
                       stack,
                       t_section_blocks,
)
from .impulse import BlockImpulse, block_impulse, failing_body
from .limit import BlockLimitResult, equilibrium_residual, solve_blocks
from .output import (
                       contact_records,
                       plot_blocks_mechanism,
                       write_blocks_vtu,
                       write_contacts_vtu,
)
from .studies import (
                       BlocksAnalysis,
                       analyse_blocks,
                       h_scan_blocks,
                       homogenisation_study,
                       table1_blocks,
)

__all__ = [
    "Assembly", "Interfaces", "find_interfaces", "from_rectangles", "running_bond_panel",
    "stack", "t_section_blocks",
    "BlockLimitResult", "solve_blocks", "equilibrium_residual",
    "BlockImpulse", "block_impulse", "failing_body",
    "contact_records", "plot_blocks_mechanism", "write_blocks_vtu", "write_contacts_vtu",
    "BlocksAnalysis", "analyse_blocks", "h_scan_blocks", "homogenisation_study",
    "table1_blocks",
]
