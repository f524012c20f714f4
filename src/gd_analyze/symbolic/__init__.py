"""Customized symbolic models: base inertial parameters, the recursive Newton-Euler program
with numeric parameters folded in, and its pruning with an error bound.

- :mod:`gd_analyze.dynamics.base_parameters`: standard inertial parameters per link, the numeric joint-torque
  regressor and the base parameters (Khalil & Kleinfinger 1987; Gautier 1990);
- :mod:`.newton_euler`: the symbolic quantities of the customized recursive Newton-Euler
  algorithm (forward and backward recursions, split by parts of the torque);
- :mod:`.recursive`: the exact model as straight-line code (a
  :class:`gd_analyze.symbolic.codegen.Program`);
- :mod:`.pruning`: dropping the smallest (base parameter, part) contributions within a
  per-joint error budget.
"""
