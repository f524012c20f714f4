"""core.dynamics"""
