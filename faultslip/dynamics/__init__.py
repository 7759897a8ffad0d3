"""The spring-slider and its solution methods: closed form (eq. 2-19), exact cycle, critical rate,
event-driven simulation, the regularised baseline, the vectorised cell kernel, and the method interface with
``auto``.
"""
