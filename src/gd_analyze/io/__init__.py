"""Files: atomic writes and hashes, trajectory CSV reading and planning, every dataset schema (HDF5 via xarray).

Reads and writes what the workflows compute; it computes no dynamics of its own beyond planning.
May import ``gd_analyze.core``, ``gd_analyze.formulations`` and ``gd_analyze.errors``.
"""
