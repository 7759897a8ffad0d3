"""Evaluating the methods themselves: the work-precision benchmark and the stability map.
"""
