"""Trajectories: reading them, planning them, excitation, recordings and their signals."""
