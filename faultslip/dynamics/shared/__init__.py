"""Machinery every dynamics family shares: the cycle result, the method assessment and the
Dormand-Prince tableau."""
