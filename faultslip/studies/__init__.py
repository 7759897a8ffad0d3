"""Gridded studies (grid specification and evaluation), out-of-core streaming, and regional maps.
"""
