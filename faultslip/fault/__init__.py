"""Fault scale: the slider per unit fault area (seed 003 §5-2), its inverse, and scenes (TOML files).
"""
