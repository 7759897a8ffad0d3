"""The rate-and-state slider: velocity steps and quasi-dynamic earthquake cycles, with their compiled
kernel and method declarations."""
