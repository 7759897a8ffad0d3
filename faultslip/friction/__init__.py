"""Friction laws and the materials that carry them: static and kinetic laws (seed 003 eq. 2-18,
Cameron's time-of-stick law), Table I and the lithologies, the user registry of fits, and fitting eq. 2-18
to laboratory data.
"""
