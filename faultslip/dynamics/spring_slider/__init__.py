"""Seed 003's spring-slider: the system, its closed form, exact cycle, critical rate, event-driven and
regularised simulation."""
