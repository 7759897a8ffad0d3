"""Figures in the seeds' conventions (matplotlib, imported where used).
"""
