"""The chapter's other formulations and the references: Lagrange-Euler, Newton-Euler, Pinocchio, operation counts.

Each computes D, h, c or tau for a :class:`gd_analyze.core.model.robot.Robot`; ``compare`` sets them side by side.
May import ``gd_analyze.core`` and ``gd_analyze.errors``; nothing from io, workflows, reports or the CLI.
"""
