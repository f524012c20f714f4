"""Workflows: the per-trajectory analysis, the sweep on dask, the closed-loop check, the evaluation of a model.

Each ties core computations to the io layer; none parses command-line arguments or draws a report.
May import ``gd_analyze.core``, ``gd_analyze.formulations``, ``gd_analyze.io`` and ``gd_analyze.errors``.
"""
