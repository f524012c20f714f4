"""Core dynamics: robot model, kinematics, the G-D terms and their kernels, ranking, simplified and explicit models.

Pure functions on arrays batched over set points, and frozen dataclasses; no files, no reports.
May import only the standard library, numpy/scipy/sympy/symengine/numba, and ``gd_analyze.errors``.
"""
