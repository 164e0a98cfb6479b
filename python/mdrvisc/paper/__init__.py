"""Reproduction of Kürschner & Filippov (2012) and the studies around it, apart from the
library proper.

The paper's scenes are scene files (``examples/paper/*.toml``, shipped as
``mdrvisc/paper/scenes/``), which :mod:`mdrvisc.paper.runs` reads when a study runs, and which
the Rust binary's ``paper`` command runs too. :mod:`mdrvisc.paper.studies` runs the paper's
comparisons (the flat rod of Section 5, the paraboloids of Section 6), the viscoelastic
unloading against Ting's closed form and the error-against-run-time study, and returns plain
data; :mod:`mdrvisc.paper.report` turns that data into text tables, CSV/JSON files and
figures. ``mdrvisc paper`` (:mod:`mdrvisc.cli`) runs both.

This subpackage is the only part of mdrvisc that uses matplotlib, an optional dependency
(``pip install 'mdrvisc[paper]'``), and only inside the plotting functions: importing it
does not import matplotlib, and the tables and files need none.
"""

from . import report, runs, studies
from .report import (
    error_table,
    orders_table,
    paper_document,
    paraboloid_tables,
    plot_error_vs_runtime,
    plot_paraboloids,
    plot_rod,
    plot_viscoelastic,
    rod_table,
    viscoelastic_table,
    write_error_vs_runtime,
    write_paper,
)
from .studies import error_vs_runtime, paper, paper_paraboloids, paper_rod, viscoelastic

__all__ = ["studies", "report", "runs", "paper", "paper_rod", "paper_paraboloids", "viscoelastic",
           "error_vs_runtime", "write_paper", "write_error_vs_runtime", "paper_document",
           "rod_table", "paraboloid_tables", "viscoelastic_table", "error_table", "orders_table",
           "plot_rod", "plot_paraboloids", "plot_viscoelastic", "plot_error_vs_runtime"]
