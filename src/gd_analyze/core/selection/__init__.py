"""core.selection"""
