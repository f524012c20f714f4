"""Reports: HTML (Jinja2) and PDF (Typst) for the main job, the sweep and the closed-loop check.

A report reads a stored dataset and never recomputes dynamics.
May import ``gd_analyze.io``, ``gd_analyze.core`` constants (labels, classes) and ``gd_analyze.errors``.
"""
